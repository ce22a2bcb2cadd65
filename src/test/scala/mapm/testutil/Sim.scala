package mapm.testutil

import chisel3._
import chiseltest._
import chiseltest.simulator.{VerilatorFlags, WriteFstAnnotation}
import firrtl2.AnnotationSeq
import mapm.sim.VerilatorPipe
import org.scalatest.TestSuite

/** The layer between our hardware tests and the simulators: a spec that simulates hardware mixes
  * this in and reaches a simulator through its two methods only.
  *
  *  - [[simulate]]: cycle-level poke, peek and step through chiseltest 6 (Verilator by default; a
  *    move to ChiselSim changes this method only). Waveforms are off by default; `MAPM_WAVES=1`
  *    writes an FST per test under test_run_dir/. `MAPM_SIM=treadle` runs on the built-in
  *    interpreter instead of Verilator (slow; for machines without Verilator).
  *  - [[pipe]]: a typed [[mapm.sim.VerilatorPipe]] for streaming millions of rows, one per cycle,
  *    through the emitted SystemVerilog (always Verilator, builds kept in the build cache,
  *    [[mapm.sim.BuildCache]]).
  *
  * The Verilator runners of whole units in [[mapm.sim]] (SoaRunner, ShaderChainRunner,
  * TsaRunner), which the CLI shares, are built on the same typed pipe.
  */
trait Sim extends ChiselScalatestTester { this: TestSuite =>

  /** Annotations for every simulation: backend choice and optional waveform dump. */
  def simAnnotations: AnnotationSeq = {
    val backend =
      if (sys.env.get("MAPM_SIM").contains("treadle")) Seq.empty
      else Seq(VerilatorBackendAnnotation, VerilatorFlags(Seq("-O1", "--x-assign", "fast", "--x-initial", "fast")))
    val waves = if (sys.env.get("MAPM_WAVES").contains("1")) Seq(WriteFstAnnotation) else Seq.empty
    backend ++ waves
  }

  /** Elaborates `gen` and runs `body` against it in the simulator. */
  def simulate[T <: Module](gen: => T)(body: T => Unit): Unit =
    test(gen).withAnnotations(simAnnotations)(body)

  /** Elaborates `gen` and builds (or finds cached) its Verilator pipe, typed by the module's
    * fields `in` and `out` (see [[mapm.sim.VerilatorPipe.of]]); modules whose names start with one
    * of `noInline` stay their own C++ classes. */
  def pipe[M <: RawModule](gen: => M, noInline: Seq[String] = Seq.empty)(in: M => Data, out: M => Data): VerilatorPipe =
    VerilatorPipe.of(gen, noInline = noInline)(in, out)
}

/** Locating `../shared` (the dissertation, design notes and test vectors) from the project root.
  * Tests that need it cancel with a clear message when it is absent. */
object SharedDir {
  /** `../shared` relative to the project root, or MAPM_SHARED when set. */
  val path: java.nio.file.Path = {
    val env = sys.env.get("MAPM_SHARED").map(java.nio.file.Paths.get(_))
    env.getOrElse(java.nio.file.Paths.get("..", "shared")).toAbsolutePath.normalize
  }
  def exists: Boolean = java.nio.file.Files.isDirectory(path)
  def file(rel: String): java.nio.file.Path = path.resolve(rel)
}
