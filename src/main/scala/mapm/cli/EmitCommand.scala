package mapm.cli

import mapm.pipeline.Configure

import mapm.sim._

import java.nio.charset.StandardCharsets.UTF_8
import java.nio.file.{Files, Paths}
import mainargs.{Flag, ParserForMethods, arg, main}
import mapm.MapmError
import mapm.format.SlotLayout
import mapm.numerics.{Arith, FloatFormat}
import mapm.sim.{Emit, EmitFiles}
import mapm.params.{Fidelity, MapmParams}
import mapm.top.Mapm
import Args.{ArithReader, FidelityReader, FloatFormatReader, SlotLayoutReader, hwOptionsParser}

/** `mapm emit`: writes the SystemVerilog of a whole MAPM ([[Mapm]]) of any size and format
  * through CIRCT, as the files an ASIC or FPGA flow takes ([[EmitFiles]]): the design, the
  * memories' and black boxes' behavioural models in files of their own (to be replaced), the file
  * list, the memory configuration in firtool's `--repl-seq-mem` format and a JSON manifest; and
  * `mapm_config.h` with the same parameters for a C++ harness. Prints the files, the elaboration
  * time, the line count, the flip-flops and what must be replaced. */
object EmitCommand extends Command {
  val name = "emit"
  val summary = "emit a whole MAPM of any TSM/SOM/SOA count and format as SystemVerilog, with its file list, memory manifest and mapm_config.h"

  @main
  def emit(
      @arg(doc = "Tree Search Modules") tsm: Int = 16,
      @arg(doc = "Shader Operation Modules") som: Int = 16,
      @arg(doc = "SOAs per SOM") soa: Int = 2,
      @arg(doc = "number format") format: FloatFormat = FloatFormat.fp32,
      @arg(doc = "memory records: packed (format slots of 2, 4 or 8 bytes, the smallest that fits) or wide (at least 4)") layout: SlotLayout = SlotLayout.Packed,
      @arg(name = "g", doc = "guard digits of the SOA's online units") g: Int = 3,
      @arg(doc = "arithmetic of the SOAs and TSAs: online (the dissertation's) or conventional (correctly rounded floating point)") arith: Arith = Arith.Online,
      @arg(doc = "full: the SOAs' arithmetic; timing: each SOA a latency-exact delay line (cycle-exact, no colours; docs/harness.md)") fidelity: Fidelity = Fidelity.Full,
      @arg(doc = "output directory") out: String = "out/mapm",
      @arg(doc = "emit beyond the generator's size limit (more TSMs and SOMs together than mapm.sim.MapmRtl.MaxEmitModules; firtool may run for hours)") beyondLimit: Flag,
      hw: HwOptions
  ): Int = {
    val p = Configure.of(tsm, som, soa, format, g, layout, arith, fidelity, hw.tuning)
    val top = mapm.sim.MapmRtl.topName(p)
    mapm.sim.MapmRtl.checkEmittable(p, beyondLimit.value)
    val dir = Paths.get(out)
    val t0 = System.nanoTime()
    val sv = Emit.systemVerilog(if (p.sim.coproc) new mapm.soc.MapmCoproc(p) else new Mapm(p))
    val design = EmitFiles.read(sv, top)
    // The coprocessor's C header of its registers (mapm_regs.h) beside its harness header.
    val headers = if (p.sim.coproc) Seq("mapm_config.h" -> mapm.sim.CoprocHarnessHeader(p, top), "mapm_regs.h" -> mapm.format.RegisterMap.cHeader)
      else Seq("mapm_config.h" -> mapm.sim.HarnessHeader(p))
    val files =
      try design.write(dir) ++ headers.map { case (f, text) => Files.write(dir.resolve(f), text.getBytes(UTF_8)) }
      catch { case e: java.io.IOException => MapmError.fail(s"$name: cannot write into $out: ${e.getMessage}") }
    val secs = (System.nanoTime() - t0) / 1e9
    println(f"emitted $top (${p.counts.label}, format ${p.numbers.format} in ${p.slotBytes}-byte slots, $arith arithmetic, g = $g${if (fidelity == Fidelity.Timing) ", SOAs as timing models" else ""}) in $secs%.1f s")
    println(s"  ${sv.linesIterator.size} lines of SystemVerilog, ${SvStats.registerBits(sv, top)} flip-flops " +
      s"(memory arrays not counted), ${p.counts.som * p.counts.soaPerSom} result ports")
    val units = for (unit <- Seq("TSA", "SOA"); m <- SvStats.modules(sv).find(m => m.startsWith(unit + "_") || m.startsWith("Conv" + unit + "_")))
      yield s"$unit ($m) ${SvStats.registerBits(sv, m)}"
    println(s"  flip-flops per ${units.mkString(", per ")}")
    val mems = design.memories
    println(f"  to replace: ${mems.size} memory modules, ${mems.map(_.instances.size).sum} instances, ${mems.map(m => m.bits * m.instances.size).sum / 8192.0}%.0f KiB " +
      s"(${top}_memories.conf); black boxes ${design.blackBoxes.map(b => s"${b.module} x${b.instances.size}").mkString(", ")} (${top}_manifest.json)")
    files.foreach(f => println(s"wrote $f"))
    0
  }

  lazy val parser: ParserForMethods[_] = ParserForMethods(this)

  def run(args: Seq[String]): Int = Args.run(this, args)
}
