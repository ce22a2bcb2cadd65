package mapm.cli

import java.io.PrintStream
import java.nio.charset.StandardCharsets
import java.nio.file.{Files, Paths}
import mainargs.{Flag, ParserForMethods, arg, main}
import mapm.MapmError
import mapm.numerics.{Arith, ConvTsaModel, FloatFormat, TsaModel, TsaVectors}
import mapm.sim.TsaRunner
import Args.{ArithReader, FloatFormatReader}

/** `mapm tsa-vectors`: runs (p, h, s) rows of a CSV file ([[TsaVectors]]) through the TSA model and, with `--hw`,
  * through the emitted TSA in Verilator; writes the outputs and checks any expected ones.
  * The file format is described in docs/tsa.md. */
object TsaVectorsCommand extends Command {
  val name = "tsa-vectors"
  val summary = "run p,h,s vectors (CSV, hex) through the TSA model and optionally its Verilog"

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
    val rows = TsaVectors.parse(new String(Files.readAllBytes(path), StandardCharsets.UTF_8), format, in)
    val model = rows.map(r => if (arith == Arith.Online) TsaModel.evaluate(format, r.p, r.h, r.s) else ConvTsaModel.evaluate(format, r.p, r.h, r.s))
    val hardware = if (!hw.value) None else {
      System.err.println(s"$name: building the Verilator simulation of the $format $arith TSA (cached after the first build) ...")
      Some(TsaRunner.run(format, rows.map(r => (r.p, r.h, r.s)), arith = arith))
    }

    val csv = TsaVectors.csv(format, rows, model, hardware)
    val report: PrintStream = out match {
      case Some(o) =>
        try Files.write(Paths.get(o), csv.toString.getBytes(StandardCharsets.UTF_8))
        catch { case e: java.io.IOException => MapmError.fail(s"$name: cannot write $o: ${e.getMessage}") }
        Console.out
      case None => Console.out.print(csv); Console.out.flush(); Console.err
    }

    val bad = rows.indices.flatMap(i => TsaVectors.mismatch(rows(i), model(i), hardware.map(_(i))).map(i -> _))
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
