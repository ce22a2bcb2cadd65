package mapm.evaluation

import java.awt.Color
import java.nio.charset.StandardCharsets.UTF_8
import java.nio.file.{Files, Path}

import mapm.MapmError
import mapm.costflow.UnitCostCache
import mapm.format.SlotLayout
import mapm.model.{ImageIO, Metrics, RgbImage}
import mapm.numerics.{Arith, FloatFormat, Vec3}
import mapm.params.{Fidelity, MapmParams}
import mapm.pipeline.{RtlRun, RunSettings, Tuning}
import mapm.sim.Harness
import org.knowm.xchart.{BitmapEncoder, XYChartBuilder}
import org.knowm.xchart.XYSeries.XYSeriesRenderStyle

/** The precision-energy study (`tools/mapm precision`, docs/precision.md): for each number format,
  * arithmetic (online with its guard digits g, or conventional) it renders the frame in the
  * model, which the RTL matches bit for bit (MapmRtlSpec), and reports
  *  - the frame's quality against float64: the indirect light's PSNR, and the mean FLIP error of
  *    the viewable frame (direct plus indirect light, 8-bit sRGB PNG) against float64's ([[Flip]]);
  *  - the SOA's and TSA's area, fmax and dynamic energy per operation from the cost flow at the
  *    frame's activity ([[UnitCostCache]]: each unit synthesized and simulated once per machine),
  *    and the arithmetic's energy per shader operation, the SOA's plus the TSA's times the frame's
  *    tree-search operations per shader operation;
  *  - optionally the frame's cycles at a configuration (16/16/2 by default) from a timing-fidelity
  *    render, and its time at the slower unit's fmax.
  * Each point's figures are kept in `out/points/<name>.json` with a key of everything that decides
  * them, so a killed study resumes where it stopped. */
object PrecisionStudy {
  /** One study point; g is the online SOA's guard digits (the conventional units have none). */
  final case class Point(format: FloatFormat, arith: Arith, g: Int) {
    def name: String = s"$format-${arith.name}" + (if (arith == Arith.Online) s"-g$g" else "")
  }

  /** A point's figures; `frameCycles` and `frameConfig` are absent when the frame time was not asked for. */
  final case class Row(point: Point, psnrDb: Double, flip: Double, levels: LevelDiff, shaderOps: Long, treeSearchOps: Long,
                       soa: UnitCostCache.Figures, tsa: UnitCostCache.Figures, frameConfig: Option[String], frameCycles: Option[Long]) {
    /** The SOA's and TSA's dynamic energy per shader operation (nJ). */
    def arithNjPerSo: Double = soa.energyPerOpNj + tsa.energyPerOpNj * treeSearchOps / shaderOps.toDouble
    /** The slower unit's fmax, the clock of the frame time. */
    def clockGHz: Double = soa.fmaxGHz min tsa.fmaxGHz
    def frameMs: Option[Double] = frameCycles.map(_ / clockGHz / 1e6)
  }

  /** How the viewable frame's 8-bit PNG differs from float64's: the largest difference of one
    * channel in levels (0 to 255) and the share of pixels that differ at all. */
  final case class LevelDiff(maxLevels: Int, pixelsDiffering: Double) {
    /** Visually lossless by this study's rule: no channel of any pixel more than one level off. */
    def lossless: Boolean = maxLevels <= 1
  }

  /** [[LevelDiff]] of two PNG files of one size. */
  def levelDiff(reference: Path, test: Path): LevelDiff = {
    def read(p: Path) = Option(javax.imageio.ImageIO.read(p.toFile)).getOrElse(MapmError.fail(s"$p: not a readable image"))
    val (a, b) = (read(reference), read(test))
    MapmError.check(a.getWidth == b.getWidth && a.getHeight == b.getHeight, s"$test is ${b.getWidth}x${b.getHeight}, $reference ${a.getWidth}x${a.getHeight}")
    val diffs = for (y <- 0 until a.getHeight; x <- 0 until a.getWidth) yield {
      val (p, q) = (a.getRGB(x, y), b.getRGB(x, y))
      (0 until 3).map(c => math.abs(((p >> (8 * c)) & 0xff) - ((q >> (8 * c)) & 0xff))).max
    }
    LevelDiff(diffs.max, diffs.count(_ > 0).toDouble / diffs.size)
  }

  /** Which of `points` (cost, error: both the lower the better) no other point dominates (no
    * higher in either and lower in one). */
  def paretoFront(points: Seq[(Double, Double)]): Seq[Boolean] =
    points.map { case (c, e) => !points.exists { case (c2, e2) => c2 <= c && e2 <= e && (c2 < c || e2 < e) } }

  /** The row of the narrowest format (fewest bits) that `lossless` accepts, the least arithmetic
    * energy per shader operation among that format's accepted rows. */
  def recommend(rows: Seq[Row], lossless: Row => Boolean): Option[Row] =
    rows.filter(lossless).sortBy(r => (r.point.format.width, r.arithNjPerSo)).headOption

  private def frameImage(prep: RtlRun.Prepared, indirect: Array[Double]): RgbImage = {
    val f = prep.frame
    RgbImage(f.width, f.height, Array.tabulate(f.pixels)(p => Vec3(indirect(3 * p), indirect(3 * p + 1), indirect(3 * p + 2)) + f.direct(p)))
  }

  /** Runs (or resumes) the study of `points` on `scene` into `out`; `frameAt` the configuration
    * whose frame time is measured (None: skipped). */
  def run(points: Seq[Point], scene: String, frameAt: Option[(Int, Int, Int)], out: Path, threads: Int, log: String => Unit): Seq[Row] = {
    MapmError.check(points.nonEmpty, "precision: no study points")
    Files.createDirectories(out.resolve("points"))
    // Everything that decides a point's figures: the model, hardware and harness sources, the cost
    // flow's, the tools' versions, the scene and the frame-time configuration.
    val costflow = Files.list(mapm.sim.Harness.root.resolve("src/main/scala/mapm/costflow")).toArray.map(_.asInstanceOf[Path]).sortBy(_.toString)
      .map(f => new String(Files.readAllBytes(f), UTF_8)).mkString
    val code = mapm.sim.Verilator.hash(RunArchive.codeHash, costflow, mapm.cost.CostTools.versions, Flip.version)
    val references = scala.collection.mutable.Map.empty[FloatFormat, (Array[Double], Path)]
    points.map { pt =>
      val file = out.resolve("points").resolve(s"${pt.name}.json")
      val key = mapm.sim.Verilator.hash(code, RecordVersion, pt.toString, scene, new String(Files.readAllBytes(java.nio.file.Paths.get(scene)), UTF_8), frameAt.toString)
      val kept = if (Files.isRegularFile(file)) scala.util.Try(ujson.read(Files.readAllBytes(file))).toOption.filter(_("key").str == key) else None
      val j = kept.getOrElse {
        log(s"${pt.name}: the model frame in ${pt.format} ${pt.arith} ...")
        val work = out.resolve("work").resolve(pt.name)
        val prep = RtlRun.prepare(scene, Some(pt.format), pt.g, work.toString, threads, arith = pt.arith)
        val (ref, refPng) = references.getOrElseUpdate(pt.format, {
          val r = RtlRun.reference(prep, threads)
          val png = out.resolve("work").resolve(s"${pt.format}-float64.png")
          ImageIO.writePng(png, frameImage(prep, r)); (r, png)
        })
        val png = work.resolve(s"${pt.name}.png")
        ImageIO.writePng(png, frameImage(prep, prep.model.frame))
        val psnr = Metrics.psnr(prep.model.frame, ref)
        val flip = Flip.meanError(refPng, png)
        val levels = levelDiff(refPng, png)
        val soa = UnitCostCache.get("soa", pt.format, pt.g, pt.arith, log)
        val tsa = UnitCostCache.get("tsa", pt.format, pt.g, pt.arith, log)
        val cycles = frameAt.map { counts =>
          log(s"${pt.name}: the frame's cycles at ${counts._1}/${counts._2}/${counts._3} (timing fidelity) ...")
          val settings = RunSettings(scene, Some(pt.format), SlotLayout.Packed, pt.g, pt.arith, Fidelity.Timing, Harness.RunOptions(),
            work.toString, threads, Tuning())
          val RtlRun.Setup(Seq(p), fprep) = settings.setup(Seq(counts))
          val r = RtlRun.runConfig(fprep, p, settings.harness, fprep.work, log, progress = false)
          MapmError.check(r.passed, s"precision: the ${pt.name} frame at ${p.counts.label} failed: ${r.failure}")
          r.outcome.stats.get.cycles
        }
        val rec = ujson.Obj("key" -> key, "point" -> pt.name, "format" -> pt.format.toString, "arith" -> pt.arith.name, "g" -> pt.g,
          "psnrDb" -> (if (psnr.isInfinite) ujson.Str("inf") else ujson.Num(psnr)), "flip" -> flip,
          "pngMaxLevels" -> levels.maxLevels, "pngPixelsDiffering" -> levels.pixelsDiffering,
          "shaderOps" -> prep.model.count.toDouble, "treeSearchOps" -> prep.model.tsOps.toDouble,
          "soa" -> soa.json, "tsa" -> tsa.json,
          "frameConfig" -> frameAt.fold[ujson.Value](ujson.Null)(c => s"${c._1}/${c._2}/${c._3}"),
          "frameCycles" -> cycles.fold[ujson.Value](ujson.Null)(c => ujson.Num(c.toDouble)))
        Files.write(file, ujson.write(rec, indent = 2).getBytes(UTF_8))
        rec
      }
      def num(v: ujson.Value): Double = v.strOpt.fold(v.num)(_ => Double.PositiveInfinity)
      Row(pt, num(j("psnrDb")), j("flip").num, LevelDiff(j("pngMaxLevels").num.toInt, j("pngPixelsDiffering").num), j("shaderOps").num.toLong, j("treeSearchOps").num.toLong,
        UnitCostCache.parse("soa", j("soa"), file), UnitCostCache.parse("tsa", j("tsa"), file),
        j("frameConfig").strOpt, j("frameCycles").numOpt.map(_.toLong))
    }
  }

  /** The rows as CSV (one line per point). */
  def csv(rows: Seq[Row]): String = {
    val front = paretoFront(rows.map(r => (r.arithNjPerSo, r.flip)))
    ("point,format,bits,arith,g,psnr_db,flip,png_max_levels,png_pixels_differing,soa_area_um2,soa_nj_per_op,soa_fmax_ghz,tsa_area_um2,tsa_nj_per_op,tsa_fmax_ghz," +
      "arith_nj_per_so,frame_config,frame_cycles,frame_ms,pareto\n") + rows.zip(front).map { case (r, p) =>
      Seq(r.point.name, r.point.format.toString, r.point.format.width, r.point.arith.name, r.point.g, f"${r.psnrDb}%.3f", f"${r.flip}%.6f",
        r.levels.maxLevels, f"${r.levels.pixelsDiffering}%.5f", f"${r.soa.areaUm2}%.0f", f"${r.soa.energyPerOpNj}%.4f", f"${r.soa.fmaxGHz}%.4f", f"${r.tsa.areaUm2}%.0f", f"${r.tsa.energyPerOpNj}%.4f",
        f"${r.tsa.fmaxGHz}%.4f", f"${r.arithNjPerSo}%.4f", r.frameConfig.getOrElse(""), r.frameCycles.fold("")(_.toString),
        r.frameMs.fold("")(v => f"$v%.4f"), p).mkString(",")
    }.mkString("\n") + "\n"
  }

  /** The rows as a markdown table, the Pareto front's rows marked. */
  def table(rows: Seq[Row]): String = {
    val front = paretoFront(rows.map(r => (r.arithNjPerSo, r.flip)))
    val sb = new StringBuilder
    sb ++= "| point | bits | PSNR (dB) | mean FLIP | PNG levels off (max; pixels) | SOA area (mm^2) | SOA nJ/op | SOA fmax (MHz) | TSA area (mm^2) | TSA nJ/op | " +
      "nJ per SO (SOA + TSA) | frame cycles | frame (ms) | Pareto |\n"
    sb ++= "|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|:---:|\n"
    for ((r, p) <- rows.zip(front))
      sb ++= f"| ${r.point.name} | ${r.point.format.width} | ${r.psnrDb}%.2f | ${r.flip}%.6f | ${r.levels.maxLevels}; ${r.levels.pixelsDiffering * 100}%.1f %% | ${r.soa.areaUm2 / 1e6}%.3f | ${r.soa.energyPerOpNj}%.3f | " +
        f"${r.soa.fmaxGHz * 1000}%.0f | ${r.tsa.areaUm2 / 1e6}%.3f | ${r.tsa.energyPerOpNj}%.3f | ${r.arithNjPerSo}%.3f | " +
        s"${r.frameCycles.fold("-")(c => f"$c%,d")} | ${r.frameMs.fold("-")(v => f"$v%.2f")} | ${if (p) "yes" else ""} |\n"
    sb.toString
  }

  /** The FLIP error a chart draws for 0 (its axis is logarithmic). */
  val ChartFloor = 1e-5

  /** The Pareto chart: each point's arithmetic energy per shader operation against its mean FLIP
    * error on a logarithmic axis (0 drawn at [[ChartFloor]]), one series per arithmetic, the
    * front's points named. */
  def chart(rows: Seq[Row], path: Path): Unit = {
    val chart = new XYChartBuilder().width(860).height(560).title("Precision against energy (SOA + TSA per shader operation)")
      .xAxisTitle("dynamic energy per shader operation (nJ)").yAxisTitle(s"mean FLIP error against float64 (0 drawn at $ChartFloor)").build()
    val style = chart.getStyler
    style.setYAxisLogarithmic(true)
    style.setDefaultSeriesRenderStyle(XYSeriesRenderStyle.Scatter)
    style.setChartBackgroundColor(Color.WHITE); style.setPlotBackgroundColor(Color.WHITE)
    style.setMarkerSize(10)
    val front = paretoFront(rows.map(r => (r.arithNjPerSo, r.flip)))
    for ((label, sel) <- Seq("online" -> ((r: Row) => r.point.arith == Arith.Online), "conventional" -> ((r: Row) => r.point.arith == Arith.Conventional));
         rs = rows.filter(sel) if rs.nonEmpty)
      chart.addSeries(label, rs.map(_.arithNjPerSo).toArray, rs.map(_.flip max ChartFloor).toArray)
    val onFront = rows.zip(front).filter(_._2).map(_._1).sortBy(_.arithNjPerSo)
    if (onFront.size >= 2) chart.addSeries("Pareto front", onFront.map(_.arithNjPerSo).toArray, onFront.map(_.flip max ChartFloor).toArray)
      .setXYSeriesRenderStyle(XYSeriesRenderStyle.Line)
    for (r <- onFront) chart.addAnnotation(new org.knowm.xchart.AnnotationText(r.point.name, r.arithNjPerSo, (r.flip max ChartFloor) * 1.6, false))
    Option(path.toAbsolutePath.getParent).foreach(Files.createDirectories(_))
    Files.write(path, BitmapEncoder.getBitmapBytes(chart, BitmapEncoder.BitmapFormat.PNG))
  }

  /** The version of a point's record: a record of another version is made again. */
  private val RecordVersion = "2"

  /** The configuration whose frame time the study measures unless told otherwise. */
  val defaultFrameConfig: (Int, Int, Int) = (MapmParams.default.counts.tsm, MapmParams.default.counts.som, MapmParams.default.counts.soaPerSom)
}
