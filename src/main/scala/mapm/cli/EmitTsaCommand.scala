package mapm.cli

import java.nio.file.Paths
import mainargs.{ParserForMethods, arg, main}
import mapm.MapmError
import mapm.fpu.FpuDepth
import mapm.numerics.{Arith, FloatFormat, TsaModel}
import mapm.sim.Emit
import mapm.tsearch.{ConvTSA, TsaUnit}
import Args.ArithReader

/** `mapm emit-tsa`: writes the SystemVerilog of the Tree Search Accelerator for a float format. */
object EmitTsaCommand extends Command {
  val name = "emit-tsa"
  val summary = "write the Tree Search Accelerator's SystemVerilog (any float format) through CIRCT"

  /** The format from `--format`, or else from `--exp` and `--man`; both at once is an error. */
  private[cli] def formatOf(format: Option[String], exp: Option[Int], man: Option[Int]): FloatFormat =
    format match {
      case Some(f) =>
        MapmError.check(exp.isEmpty && man.isEmpty, s"$name: give either --format or --exp/--man, not both")
        FloatFormat.parse(f)
      case None => FloatFormat.parse(s"${exp.getOrElse(8)},${man.getOrElse(23)}")
    }

  @main
  def emitTsa(
      @arg(doc = "exponent width in bits, 2..11 (default 8)") exp: Option[Int] = None,
      @arg(doc = "mantissa width in bits without the hidden bit, 1..52 (default 23)") man: Option[Int] = None,
      @arg(doc = "float format instead of --exp/--man: fp32, bf16, fp16, fp24, fp64 or E,M") format: Option[String] = None,
      @arg(doc = "width of the opaque tag that travels with each operation, 1..64") tagWidth: Int = 16,
      @arg(doc = "online (the digit-serial comparators) or conventional (two FAdds, exact decisions)") arith: Arith = Arith.Online,
      @arg(doc = "output directory (created when missing)") out: String = "."
  ): Int = {
    val fmt = formatOf(format, exp, man)
    MapmError.check(tagWidth >= 1 && tagWidth <= 64, s"$name: --tag-width must be 1..64, got $tagWidth")
    val add = FpuDepth.of(fmt).add
    val file = TsaUnit.name(fmt, tagWidth, stallable = false, arith, add) + ".sv"
    val path =
      try Emit.toFile(TsaUnit(fmt, tagWidth, stallable = false, arith, add), Paths.get(out), file)
      catch { case e: java.io.IOException => MapmError.fail(s"$name: cannot write $out/$file: ${e.getMessage}") }
    if (arith == Arith.Online)
      println(s"wrote $path: TSA for $fmt, tag $tagWidth bits, latency ${TsaModel.latency(fmt)} cycles, " +
        s"${TsaModel.Alignment.exact.wordWidth(fmt)} comparator slices, one operation per cycle")
    else
      println(s"wrote $path: conventional TSA for $fmt, tag $tagWidth bits, latency ${ConvTSA.latency(add)} cycles " +
        s"(two $add-stage adders, one comparison cycle), one operation per cycle")
    0
  }

  lazy val parser: ParserForMethods[_] = ParserForMethods(this)

  def run(args: Seq[String]): Int = Args.run(this, args)
}
