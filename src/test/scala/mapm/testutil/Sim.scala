package mapm.testutil

import chisel3._
import chiseltest._
import chiseltest.simulator.{VerilatorFlags, WriteFstAnnotation}
import firrtl2.AnnotationSeq
import org.scalatest.TestSuite

/** The one thin layer between our hardware tests and the simulator (chiseltest 6 on Verilator
  * today; a move to ChiselSim changes this file only).
  *
  * Waveforms are off by default; `MAPM_WAVES=1` writes an FST per test under test_run_dir/.
  * `MAPM_SIM=treadle` runs on the built-in interpreter instead of Verilator (slow; for machines
  * without Verilator).
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
