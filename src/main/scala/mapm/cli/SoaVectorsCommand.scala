package mapm.cli

import java.nio.file.Paths
import mainargs.{Flag, ParserForMethods, arg, main}
import mapm.MapmError
import mapm.numerics.{Arith, CondModel, ConvChainModel, FloatFormat, ShaderChainModel, ShaderVectors}
import mapm.shader.SOA
import mapm.sim.SoaRunner
import Args.{ArithReader, FloatFormatReader}

/** `mapm soa-vectors`: runs a shader-chain vector file (../shared/vectors format) through the
  * bit-accurate model, comparing every column (result, flags, s, m, E and the digit strings;
  * with `--arith conventional` the conventional chain's files, ../shared/vectors/conventional,
  * and [[ConvChainModel]]), and with `--hw` through the emitted SystemVerilog of the [[SOA]] of
  * that arithmetic in Verilator (result and
  * flags of each row, driven on all three channels). The vectors carry no positions: the SOA
  * gets query and photon at the origin, so cond must be 0 < h·h ([[CondModel]]). Prints the mismatch count and the first mismatch of
  * each; exits 1 if there is any. */
object SoaVectorsCommand extends Command {
  val name = "soa-vectors"
  val summary = "check a shader-chain vector file against the model (and the hardware with --hw)"

  @main
  def soaVectors(
      @arg(doc = "vector file (CSV: id,kernel,brdf,h,power,contrib,expected,flags,s,m,E[,p1,q,p2,p3])") in: String,
      @arg(doc = "float format of the file") format: FloatFormat = FloatFormat.fp32,
      @arg(name = "g", doc = "guard digits the file was made with (online arithmetic)") g: Int = 3,
      @arg(doc = "arithmetic: online (the digit-serial chain) or conventional (correctly rounded, ../shared/vectors/conventional)") arith: Arith = Arith.Online,
      @arg(doc = "also run the emitted Verilog in Verilator") hw: Flag
  ): Int = {
    MapmError.check(g >= 0 && g <= 8, s"soa-vectors: --g must be 0..8, got $g")
    MapmError.check(format.manWidth >= 4, s"soa-vectors: format $format needs at least 4 fraction bits")
    val rows = ShaderVectors.read(Paths.get(in), format)
    val online = new ShaderChainModel(format, g)
    def trace(r: ShaderVectors.Row): ShaderChainModel.Trace = arith match {
      case Arith.Online => online.trace(r.kernel, r.brdf, r.h, r.power, r.contrib)
      case Arith.Conventional => ConvChainModel.trace(format, r.kernel, r.brdf, r.h, r.power, r.contrib)
    }

    val t0 = System.nanoTime()
    val modelBad = rows.iterator.flatMap(r => ShaderVectors.mismatch(r, trace(r), format))
    var modelCount = 0; var modelFirst: Option[String] = None
    modelBad.foreach { m => modelCount += 1; if (modelFirst.isEmpty) modelFirst = Some(m) }
    report("model", rows.length, modelCount, modelFirst, (System.nanoTime() - t0) / 1e9)

    val hwCount = if (!hw.value) 0 else {
      val t1 = System.nanoTime()
      val sim = SoaRunner(format, g, arith = arith)
      val t2 = System.nanoTime()
      var k = 0; var count = 0; var first: Option[String] = None
      val ops = rows.iterator.zipWithIndex.map { case (r, i) =>
        Some(SoaRunner.Op(Array(r.kernel, r.brdf, r.h, r.power, r.power, r.power, r.contrib, r.contrib, r.contrib) ++
          Array.fill(6)(0L), i & 0xffff))
      }
      sim.run(ops) { o =>
        val r = rows(k)
        val cond = CondModel.cond(format, 0L, 0L, 0L, 0L, 0L, 0L, r.h)
        val bad = (0 until 3).filter(c => o.colour(c) != r.expected || o.flags(c) != r.flags)
        if (bad.nonEmpty || o.cond != cond || o.tag != (k & 0xffff)) {
          count += 1
          if (first.isEmpty) first = Some(s"row id ${r.id} (line ${r.line}): expected ${format.hex(r.expected)} flags ${r.flags} " +
            s"cond $cond, hardware ${(0 until 3).map(c => s"${format.hex(o.colour(c))}/${o.flags(c)}").mkString(" ")} " +
            s"cond ${o.cond} (tag ${o.tag})")
        }
        k += 1
      }
      if (k != rows.length) { count += rows.length - k; if (first.isEmpty) first = Some(s"${rows.length - k} rows produced no result") }
      println(f"hardware: ${SOA.name(format, g, arith = arith)}, Verilator build ${(t2 - t1) / 1e9}%.1f s")
      report("hardware", rows.length, count, first, (System.nanoTime() - t2) / 1e9)
      count
    }
    if (modelCount + hwCount == 0) 0 else 1
  }

  private def report(what: String, rows: Int, bad: Int, first: Option[String], seconds: Double): Unit = {
    println(f"$what: $rows rows, $bad mismatches ($seconds%.1f s)")
    first.foreach(m => println(s"  first: $m"))
  }

  lazy val parser: ParserForMethods[_] = ParserForMethods(this)

  def run(args: Seq[String]): Int = Args.run(this, args)
}
