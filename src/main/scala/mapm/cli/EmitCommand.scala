package mapm.cli

import java.nio.charset.StandardCharsets.UTF_8
import java.nio.file.{Files, Paths}
import mainargs.{ParserForMethods, arg, main}
import mapm.MapmError
import mapm.format.SlotLayout
import mapm.model.{Arith, FloatFormat}
import mapm.sim.Emit
import mapm.params.{Fidelity, MapmParams}
import mapm.top.Mapm
import Args.{ArithReader, FidelityReader, FloatFormatReader, SlotLayoutReader, hwOptionsParser}

/** `mapm emit`: writes the SystemVerilog of a whole MAPM ([[Mapm]]) of any size and format
  * through CIRCT, and `mapm_config.h` with the same parameters for a C++ harness. Prints the
  * elaboration time, the line count and the flip-flops. */
object EmitCommand extends Command {
  val name = "emit"
  val summary = "emit a whole MAPM of any TSM/SOM/SOA count and format as SystemVerilog (+ mapm_config.h)"

  @main
  def emit(
      @arg(doc = "Tree Search Modules") tsm: Int = 16,
      @arg(doc = "Shader Operation Modules") som: Int = 16,
      @arg(doc = "SOAs per SOM") soa: Int = 2,
      @arg(doc = "number format: fp32, bf16, fp16, fp24, fp64 or E,M") format: FloatFormat = FloatFormat.fp32,
      @arg(doc = "memory records: packed (format slots of 2, 4 or 8 bytes, the smallest that fits) or wide (at least 4)") layout: SlotLayout = SlotLayout.Packed,
      @arg(name = "g", doc = "guard digits of the SOA's online units") g: Int = 3,
      @arg(doc = "arithmetic of the SOAs and TSAs: online (the dissertation's) or conventional (correctly rounded floating point)") arith: Arith = Arith.Online,
      @arg(doc = "full: the SOAs' arithmetic; timing: each SOA a latency-exact delay line (cycle-exact, no colours; docs/harness.md)") fidelity: Fidelity = Fidelity.Full,
      @arg(doc = "output directory") out: String = "out/mapm",
      hw: HwOptions
  ): Int = {
    val p = MapmParams.of(tsm, som, soa, format, g, layout, arith, fidelity, hw.tuning)
    val top = s"Mapm_${p.name}"
    val dir = Paths.get(out)
    val t0 = System.nanoTime()
    val file =
      try {
        val f = Emit.toFile(new Mapm(p), dir, s"$top.sv")
        Files.write(dir.resolve("mapm_config.h"), mapm.sim.HarnessHeader(p).getBytes(UTF_8))
        f
      } catch { case e: java.io.IOException => MapmError.fail(s"$name: cannot write into $out: ${e.getMessage}") }
    val secs = (System.nanoTime() - t0) / 1e9
    val sv = new String(Files.readAllBytes(file), UTF_8)
    println(f"wrote $file and ${dir.resolve("mapm_config.h")} ($top: ${p.counts.label}, format ${p.numbers.format} in ${p.slotBytes}-byte slots, $arith arithmetic, g = $g${if (fidelity == Fidelity.Timing) ", SOAs as timing models" else ""}) in $secs%.1f s")
    println(s"  ${sv.linesIterator.size} lines of SystemVerilog, ${SvStats.registerBits(sv, top)} flip-flops " +
      s"(memory arrays not counted), ${p.counts.som * p.counts.soaPerSom} result ports")
    val units = for (unit <- Seq("TSA", "SOA"); m <- SvStats.modules(sv).find(m => m.startsWith(unit + "_") || m.startsWith("Conv" + unit + "_")))
      yield s"$unit ($m) ${SvStats.registerBits(sv, m)}"
    println(s"  flip-flops per ${units.mkString(", per ")}")
    0
  }

  def run(args: Seq[String]): Int = Args.run(ParserForMethods(this), args, name)
}
