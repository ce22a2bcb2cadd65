package mapm.numerics

import mapm.MapmError
import mapm.numerics.TsaModel.Outcome

/** The TSA vector file of `mapm tsa-vectors` (docs/tsa.md): a CSV header naming the columns
  * (p, h, s required, tcl, tcr, error optional, others ignored), then one row per line of hex bit
  * patterns and 0/1 flags; and the output CSV the command writes. */
object TsaVectors {
  /** One input row: its line number, operands and the expected outputs it names. */
  final case class Row(line: Int, p: Long, h: Long, s: Long, tcl: Option[Boolean], tcr: Option[Boolean], error: Option[Boolean])

  /** Parses the CSV text: a header naming the columns (p, h, s required; tcl, tcr, error
    * optional; others ignored), then one row per line; blank lines and `#` lines are skipped. */
  def parse(text: String, fmt: FloatFormat, file: String): IndexedSeq[Row] = {
    val lines = text.linesIterator.zipWithIndex.map { case (l, i) => (l.trim, i + 1) }
      .filter { case (l, _) => l.nonEmpty && !l.startsWith("#") }
    if (!lines.hasNext) MapmError.fail(s"$file: empty (expected a header line such as 'p,h,s,tcl,tcr')")
    val (header, headerLine) = lines.next()
    val cols = header.split(",", -1).map(_.trim.toLowerCase).toIndexedSeq
    def col(n: String) = cols.indexOf(n) match { case -1 => None; case i => Some(i) }
    val Seq(ip, ih, is) = Seq("p", "h", "s").map(n => col(n).getOrElse(
      MapmError.fail(s"$file:$headerLine: header has no '$n' column (found: ${cols.mkString(",")})")))
    val (itl, itr, ie) = (col("tcl"), col("tcr"), col("error"))
    lines.map { case (l, no) =>
      val f = l.split(",", -1).map(_.trim)
      if (f.length != cols.length) MapmError.fail(s"$file:$no: ${f.length} fields, the header has ${cols.length}")
      def bits(i: Int): Long = {
        val t = f(i).stripPrefix("0x").stripPrefix("0X")
        val v = if (t.nonEmpty && t.length <= 16 && t.forall(Character.digit(_, 16) >= 0)) java.lang.Long.parseUnsignedLong(t, 16) else -1L
        if (t.isEmpty || v < 0 || (v & ~fmt.mask) != 0)
          MapmError.fail(s"$file:$no: ${cols(i)} = '${f(i)}' is not a $fmt bit pattern in hex (${fmt.width} bits)")
        v
      }
      def flag(i: Option[Int]): Option[Boolean] = i.map(k => f(k).toLowerCase match {
        case "1" | "true"  => true
        case "0" | "false" => false
        case other => MapmError.fail(s"$file:$no: ${cols(k)} = '$other' must be 0 or 1")
      })
      Row(no, bits(ip), bits(ih), bits(is), flag(itl), flag(itr), flag(ie))
    }.toIndexedSeq
  }

  def b(x: Boolean): String = if (x) "1" else "0"
  def show(o: Outcome): String = s"tcl=${b(o.tcl)} tcr=${b(o.tcr)} error=${b(o.error)}"

  /** What is wrong with a row's outputs (empty when nothing is). */
  def mismatch(r: Row, model: Outcome, hw: Option[Outcome]): Option[String] = {
    val expected = Seq(r.tcl.map(_ != model.tcl), r.tcr.map(_ != model.tcr), r.error.map(_ != model.error)).flatten
    val modelWrong = expected.contains(true)
    val hwDiffers = hw.exists(_ != model)
    if (!modelWrong && !hwDiffers) None
    else {
      val want = Seq(r.tcl.map(x => s"tcl=${b(x)}"), r.tcr.map(x => s"tcr=${b(x)}"), r.error.map(x => s"error=${b(x)}")).flatten
      Some((Seq(s"expected ${want.mkString(" ")}").filter(_ => want.nonEmpty) ++ Seq(s"model ${show(model)}") ++
        hw.map(h => s"hardware ${show(h)}")).mkString(", "))
    }
  }

  /** The output CSV: each row's operands and the model's outcome, and with `hardware` its outcome too. */
  def csv(format: FloatFormat, rows: IndexedSeq[Row], model: IndexedSeq[Outcome], hardware: Option[IndexedSeq[Outcome]]): String = {
    val sb = new StringBuilder
    sb.append("p,h,s,tcl,tcr,error").append(if (hardware.isDefined) ",hw_tcl,hw_tcr,hw_error\n" else "\n")
    for (i <- rows.indices) {
      val (r, m) = (rows(i), model(i))
      sb.append(s"${format.hex(r.p)},${format.hex(r.h)},${format.hex(r.s)},${b(m.tcl)},${b(m.tcr)},${b(m.error)}")
      hardware.foreach(h => sb.append(s",${b(h(i).tcl)},${b(h(i).tcr)},${b(h(i).error)}"))
      sb.append('\n')
    }
    sb.toString
  }
}
