package mapm.cli

import mapm.sim.SvStats

import java.nio.file.Paths
import mainargs.{ParserForMethods, arg, main}
import mapm.MapmError
import mapm.numerics.{Arith, FloatFormat}
import mapm.fpu.FpuDepth
import mapm.shader.{CondCheck, ConvShaderChain, SOA, ShaderChain}
import mapm.sim.Emit
import Args.{ArithReader, FloatFormatReader}

/** `mapm emit-soa`: writes the SystemVerilog of the shader-operation accelerator [[SOA]] (colour
  * chain and cond check) through CIRCT, and prints its latencies and register count. */
object EmitSoaCommand extends Command {
  val name = "emit-soa"
  val summary = "emit the SOA (colour chain and cond check) as SystemVerilog"

  @main
  def emitSoa(
      @arg(doc = "float format") format: FloatFormat = FloatFormat.fp32,
      @arg(name = "g", doc = "guard digits per online unit (0 = the dissertation's N = n)") g: Int = 3,
      @arg(doc = "width of the opaque tag that travels with each operation") tagWidth: Int = 16,
      @arg(doc = "colour chain: online (the digit-serial units) or conventional (7 FMul + 1 FDiv)") arith: Arith = Arith.Online,
      @arg(doc = "output directory") out: String = "out/soa"
  ): Int = {
    MapmError.check(g >= 0 && g <= 8, s"emit-soa: --g must be 0..8, got $g")
    MapmError.check(format.manWidth >= 4 || arith == Arith.Conventional, s"emit-soa: format $format needs at least 4 fraction bits")
    MapmError.check(tagWidth >= 1 && tagWidth <= 64, s"emit-soa: --tag-width must be 1..64, got $tagWidth")
    val top = SOA.name(format, g, arith = arith)
    val depth = FpuDepth.of(format)
    val file =
      try Emit.toFile(new SOA(format, g, tagWidth, arith = arith), Paths.get(out), s"$top.sv")
      catch { case e: java.io.IOException => MapmError.fail(s"$name: cannot write $out/$top.sv: ${e.getMessage}") }
    val sv = new String(java.nio.file.Files.readAllBytes(file), "UTF-8")
    val units = (arith match {
      case Arith.Online =>
        println(s"wrote $file ($top: format $format, g = $g, N = ${format.manWidth + 1 + g} digits per unit)")
        ShaderChain.unitLatencies(format, g)
      case Arith.Conventional =>
        println(s"wrote $file ($top: format $format, conventional: 7 FMul, 1 FDiv)")
        Seq("FMul" -> depth.mul, "FDiv (radix-2 SRT)" -> depth.div, "colour chain" -> ConvShaderChain.latency(depth))
    }) ++ Seq("cond check" -> CondCheck.latency(depth), "SOA (colours, flags, cond, tag)" -> SOA.latency(format, g, depth, arith))
    for ((unit, cycles) <- units) println(f"  latency $unit%-36s $cycles%3d cycles")
    println(s"  flip-flops: ${SvStats.registerBits(sv, top)}")
    0
  }

  lazy val parser: ParserForMethods[_] = ParserForMethods(this)

  def run(args: Seq[String]): Int = Args.run(this, args)
}
