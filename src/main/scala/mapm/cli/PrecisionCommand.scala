package mapm.cli

import java.nio.charset.StandardCharsets.UTF_8
import java.nio.file.{Files, Paths}

import mainargs.{Flag, ParserForMethods, arg, main}
import mapm.MapmError
import mapm.evaluation.PrecisionStudy
import mapm.numerics.{Arith, FloatFormat}
import mapm.pipeline.ModelRun

/** `mapm precision`: the precision-energy study ([[PrecisionStudy]], docs/precision.md). For each
  * format, arithmetic and guard-digit count: the frame's PSNR and mean FLIP error against float64,
  * the SOA's and TSA's area, fmax and energy per operation from the cost flow, the arithmetic's
  * energy per shader operation and, unless `--no-frame-time`, the frame's cycles at `--frame-at`
  * (a timing-fidelity render) and its time at the slower unit's fmax. Prints the table; writes
  * `precision.csv` and the Pareto chart `precision-pareto.png` into `--out`, and each point's
  * figures into `--out/points/`, from which a killed run resumes. */
object PrecisionCommand extends Command {
  val name = "precision"
  val summary = "precision-energy study: PSNR and FLIP against float64, SOA/TSA area and energy, frame time, per format"

  /** "fp16,bf16,5,7" is ambiguous, so formats are separated by ';' or spaces: "fp16;bf16;5,7". */
  def parseFormats(s: String): Seq[FloatFormat] =
    s.split("[;\\s]+").map(_.trim).filter(_.nonEmpty).toSeq.map(FloatFormat.parse)

  @main
  def precision(
      @arg(doc = "formats, separated by ';' (E,M for others)") formats: String = "fp16;bf16;5,7;fp24;fp32",
      @arg(doc = "arithmetics: online, conventional or both") arith: String = "both",
      @arg(doc = "guard digits of the online SOA, separated by ','") g: String = "3",
      @arg(doc = "scene file") scene: String = ModelRun.defaultScene,
      @arg(doc = "configuration whose frame time is measured (TSM/SOM/SOA)") frameAt: String = "16/16/2",
      @arg(doc = "skip the frame time (the timing-fidelity renders)") noFrameTime: Flag,
      @arg(doc = "worker threads of the model") threads: Int = 2,
      @arg(doc = "output folder") out: String = "out/precision"
  ): Int = {
    val fmts = parseFormats(formats)
    val ariths = arith match {
      case "both" => Arith.all
      case a => Seq(Arith.all.find(_.name == a).getOrElse(MapmError.fail(s"precision: --arith takes online, conventional or both, got '$a'")))
    }
    val gs = g.split(',').map(_.trim).filter(_.nonEmpty).map(x => x.toIntOption.filter(v => v >= 0 && v <= 8)
      .getOrElse(MapmError.fail(s"precision: --g takes guard digits 0..8 separated by ',', got '$x'"))).toSeq.distinct
    MapmError.check(fmts.nonEmpty && gs.nonEmpty, "precision: no formats or no guard digits")
    MapmError.check(threads >= 1, s"precision: --threads must be at least 1, got $threads")
    MapmError.check(Files.isRegularFile(Paths.get(scene)), s"precision: --scene $scene: no such file")
    val counts = frameAt.split('/').map(_.trim.toIntOption) match {
      case Array(Some(t), Some(m), Some(a)) => (t, m, a)
      case _ => MapmError.fail(s"precision: --frame-at takes one configuration TSM/SOM/SOA (e.g. 16/16/2), got '$frameAt'")
    }
    try mapm.params.ModuleCounts(counts._1, counts._2, counts._3) // the counts' limits
    catch { case e: IllegalArgumentException => MapmError.fail(s"precision: --frame-at $frameAt: ${e.getMessage.stripPrefix("requirement failed: ")}") }
    val frame = if (noFrameTime.value) None else Some(counts)
    val points = for (f <- fmts; a <- ariths; gg <- (if (a == Arith.Online) gs else gs.take(1)))
      yield PrecisionStudy.Point(f, a, gg)
    val dir = Paths.get(out)
    val rows = PrecisionStudy.run(points, scene, frame, dir, threads, l => System.err.println(s"mapm: $l"))
    val csv = PrecisionStudy.csv(rows)
    Files.write(dir.resolve("precision.csv"), csv.getBytes(UTF_8))
    PrecisionStudy.chart(rows, dir.resolve("precision-pareto.png"))
    println(PrecisionStudy.table(rows))
    // The recommendation: the narrowest format whose frame is visually lossless (no channel of any
    // pixel more than one 8-bit level off float64's), against fp32 in the same arithmetic.
    PrecisionStudy.recommend(rows, _.levels.lossless) match {
      case Some(r) =>
        val fp32 = rows.find(x => x.point.format == FloatFormat.fp32 && x.point.arith == r.point.arith && x.point.g == r.point.g)
        println(s"narrowest visually lossless (no channel more than one 8-bit level off float64): ${r.point.name}" +
          fp32.fold("")(b => f", ${r.arithNjPerSo}%.2f nJ per shader operation against fp32's ${b.arithNjPerSo}%.2f " +
            f"(${(1 - r.arithNjPerSo / b.arithNjPerSo) * 100}%.0f %% less), SOA ${r.soa.areaUm2 / 1e6}%.2f mm^2 against ${b.soa.areaUm2 / 1e6}%.2f"))
      case None => println("no format studied is visually lossless (no channel more than one 8-bit level off float64)")
    }
    Seq("precision.csv", "precision-pareto.png").foreach(f => println(s"wrote ${dir.resolve(f)}"))
    0
  }

  lazy val parser: ParserForMethods[_] = ParserForMethods(this)
  def run(args: Seq[String]): Int = Args.run(this, args)
}
