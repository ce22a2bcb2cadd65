package mapm.cli

import mainargs.{ParserForMethods, arg, main}
import mapm.numerics.FloatFormat
import Args.FloatFormatReader

/** `mapm format`: shows how a value is encoded in a float format (a quick check for users). */
object FormatCommand extends Command {
  val name = "format"
  val summary = "encode decimal values in a float format and show their bits"

  @main
  def format(
      @arg(doc = "float format") format: FloatFormat = FloatFormat.fp32,
      @arg(doc = "comma-separated values to encode") values: String = "1"
  ): Int = {
    println(s"format $format: exponent ${format.expWidth} bits (bias ${format.bias}), mantissa ${format.manWidth} bits, max ${format.maxFinite}, min normal ${format.minNormal}")
    for (v <- values.split(",").map(_.trim) if v.nonEmpty) {
      val d = v.toDoubleOption.getOrElse(mapm.MapmError.fail(s"format: '$v' is not a number"))
      val bits = format.encode(d, s"value '$v'")
      println(s"$v -> 0x${format.hex(bits)} = ${format.decode(bits)}")
    }
    0
  }

  lazy val parser: ParserForMethods[_] = ParserForMethods(this)

  def run(args: Seq[String]): Int = Args.run(this, args)
}
