package mapm.cli

import java.io.PrintStream
import java.nio.charset.StandardCharsets
import java.nio.file.{Files, Paths}
import mainargs.{Flag, ParserForMethods, arg, main}
import mapm.MapmError
import mapm.numerics.{Arith, ConvTsaModel, FloatFormat, TsaModel}
import mapm.numerics.TsaModel.Outcome
import mapm.sim.TsaRunner
import Args.{ArithReader, FloatFormatReader}

/** `mapm tsa-vectors`: runs (p, h, s) rows of a CSV file through the TSA model and, with `--hw`,
  * through the emitted TSA in Verilator; writes the outputs and checks any expected ones.
  * The file format is described in docs/tsa.md. */
object TsaVectorsCommand extends Command {
  val name = "tsa-vectors"
  val summary = "run p,h,s vectors (CSV, hex) through the TSA model and optionally its Verilog"

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

  private def b(x: Boolean): String = if (x) "1" else "0"
  private def show(o: Outcome): String = s"tcl=${b(o.tcl)} tcr=${b(o.tcr)} error=${b(o.error)}"

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

  @main
  def tsaVectors(
      @arg(doc = "CSV file: header line, then rows p,h,s (hex bit patterns); optional expected columns tcl,tcr,error") in: String,
      @arg(doc = "float format of the bit patterns") format: FloatFormat = FloatFormat.fp32,
      @arg(doc = "also run the rows through the emitted TSA Verilog in Verilator") hw: Flag,
      @arg(doc = "TSA: online (the digit-serial comparators) or conventional (two FAdds, exact decisions)") arith: Arith = Arith.Online,
      @arg(doc = "write the output CSV here (default: standard output, with the summary on standard error)") out: Option[String] = None
  ): Int = {
    val path = Paths.get(in)
    if (!Files.isRegularFile(path)) MapmError.fail(s"$name: input file $in not found")
    val rows = parse(new String(Files.readAllBytes(path), StandardCharsets.UTF_8), format, in)
    val model = rows.map(r => if (arith == Arith.Online) TsaModel.evaluate(format, r.p, r.h, r.s) else ConvTsaModel.evaluate(format, r.p, r.h, r.s))
    val hardware = if (!hw.value) None else {
      System.err.println(s"$name: building the Verilator simulation of the $format $arith TSA (cached after the first build) ...")
      Some(TsaRunner.run(format, rows.map(r => (r.p, r.h, r.s)), arith = arith))
    }

    val csv = new StringBuilder
    csv.append("p,h,s,tcl,tcr,error").append(if (hardware.isDefined) ",hw_tcl,hw_tcr,hw_error\n" else "\n")
    for (i <- rows.indices) {
      val (r, m) = (rows(i), model(i))
      csv.append(s"${format.hex(r.p)},${format.hex(r.h)},${format.hex(r.s)},${b(m.tcl)},${b(m.tcr)},${b(m.error)}")
      hardware.foreach(h => csv.append(s",${b(h(i).tcl)},${b(h(i).tcr)},${b(h(i).error)}"))
      csv.append('\n')
    }
    val report: PrintStream = out match {
      case Some(o) =>
        try Files.write(Paths.get(o), csv.toString.getBytes(StandardCharsets.UTF_8))
        catch { case e: java.io.IOException => MapmError.fail(s"$name: cannot write $o: ${e.getMessage}") }
        Console.out
      case None => Console.out.print(csv); Console.out.flush(); Console.err
    }

    val bad = rows.indices.flatMap(i => mismatch(rows(i), model(i), hardware.map(_(i))).map(i -> _))
    val checks = (if (rows.exists(r => r.tcl.isDefined || r.tcr.isDefined || r.error.isDefined)) Seq("expected columns") else Nil) ++
      (if (hardware.isDefined) Seq("model vs hardware") else Nil)
    report.println(s"$name: ${rows.length} rows ($format${if (hardware.isDefined) ", model and hardware" else ", model"})" +
      (if (checks.isEmpty) "" else s", ${bad.length} mismatch${if (bad.length == 1) "" else "es"} (${checks.mkString(", ")})"))
    bad.headOption.foreach { case (i, what) =>
      val r = rows(i)
      report.println(s"first mismatch: $in:${r.line}: p=${format.hex(r.p)} h=${format.hex(r.h)} s=${format.hex(r.s)}: $what")
    }
    if (bad.isEmpty) 0 else 1
  }

  lazy val parser: ParserForMethods[_] = ParserForMethods(this)

  def run(args: Seq[String]): Int = Args.run(this, args, folders = Set.empty, files = Set("--out"))
}
