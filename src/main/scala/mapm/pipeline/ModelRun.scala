package mapm.pipeline

import java.nio.file.{Files, Path, Paths}
import mapm.MapmError
import mapm.model._
import mapm.numerics._
/** The software render shared by `model` and `render`: scene file -> [[Frame]] -> tree search
  * and shading in the accelerator's arithmetic (the SOA bit for bit, [[ShadeArith.hardware]] with
  * `g` guard digits) and in float64 -> image files and stats JSON.
  *
  * Outputs in `outDir`, named after the scene (`name`):
  *  - `name.png`, `name.pfm`: the viewable frame, direct light plus the indirect light computed
  *    in the accelerator's arithmetic;
  *  - `name-indirect.png`, `name-indirect.pfm`: the indirect light alone (what the accelerator computes);
  *  - `name-stats.json`: operation counts (Table 4.10), h, timings, and the PSNR of the format's
  *    indirect image against the float64 reference.
  *
  * Stage times ([[Result.times]], `stageSeconds` in the JSON): loading the scene file, the stages
  * of [[Frame.prepare]], the two search-and-shade runs (the float64 one includes quantizing the
  * queries to binary64), and writing the four images; `wallSeconds` covers all of it and the JSON.
  */
object ModelRun {
  /** @param searchCpuSeconds process CPU seconds (all threads) during the format's search and shade */
  final case class Result(frame: Frame, indirect: Array[Double], reference: Array[Double], stats: SearchStats,
                          psnr: Double, times: StageTimes, files: Seq[Path], searchCpuSeconds: Option[Double])

  /** The scene every command renders unless told otherwise: Table 4.8's Cornell-box frame. */
  val defaultScene = "test-scenes/cornell-box/scene.json"

  /** `scene.json` is named after its folder; any other file after itself. */
  def sceneName(scene: Path): String = {
    val base = scene.getFileName.toString.stripSuffix(".json")
    val parent = Option(scene.toAbsolutePath.normalize.getParent).map(_.getFileName.toString)
    if (base == "scene") parent.getOrElse(base) else parent.map(p => s"$p-$base").getOrElse(base)
  }

  def loadScene(scene: String): SceneConfig = {
    val p = Paths.get(scene)
    MapmError.check(Files.isRegularFile(p), s"$scene: scene file not found")
    SceneConfig.load(p)
  }

  def run(scene: String, format: Option[FloatFormat], outDir: String, threads: Int, quiet: Boolean = false, g: Int = 3): Result = {
    MapmError.check(threads >= 1, s"--threads must be at least 1, got $threads")
    MapmError.check(g >= 0 && g <= 8, s"--g must be 0..8, got $g")
    val wall0 = System.nanoTime()
    val config = loadScene(scene)
    val fmt = format.orElse(config.format).getOrElse(FloatFormat.fp32)
    val arith = ShadeArith.hardware(fmt, g) // checks the format before the frame is prepared
    val loaded = System.nanoTime()
    val frame = Frame.prepare(config, fmt, threads)
    val t0 = System.nanoTime()
    val cpu0 = ProcessCpu.seconds
    val hw = Render.run(frame.map, frame.querySet, frame.pixels, arith, threads, Some("search+shade"))
    val t1 = System.nanoTime()
    val searchCpu = ProcessCpu.since(cpu0)
    val refMap = PhotonMap.fromTree(frame.map.tree, frame.photons, FloatFormat.fp64, frame.h)
    val ref = Render.run(refMap, QuerySet.build(frame.queries, FloatFormat.fp64, Some("quantize queries (float64)")),
      frame.pixels, ShadeArith.float64, threads, Some("search+shade (float64)"))
    val t2 = System.nanoTime()
    val psnr = Metrics.psnr(hw.rgb, ref.rgb)

    val out = Paths.get(outDir)
    Files.createDirectories(out)
    val name = sceneName(Paths.get(scene))
    def image(rgb: Array[Double], withDirect: Boolean): RgbImage =
      RgbImage(frame.width, frame.height, Array.tabulate(frame.pixels) { p =>
        val ind = Vec3(rgb(3 * p), rgb(3 * p + 1), rgb(3 * p + 2))
        if (withDirect) ind + frame.direct(p) else ind
      })
    val full = image(hw.rgb, withDirect = true)
    val ind = image(hw.rgb, withDirect = false)
    val files = Seq(out.resolve(s"$name.png"), out.resolve(s"$name.pfm"), out.resolve(s"$name-indirect.png"),
      out.resolve(s"$name-indirect.pfm"), out.resolve(s"$name-stats.json"))
    ImageIO.writePng(files(0), full); ImageIO.writePfm(files(1), full)
    ImageIO.writePng(files(2), ind); ImageIO.writePfm(files(3), ind)
    val t3 = System.nanoTime()
    val times = StageTimes(("load scene" -> (loaded - wall0) / 1e9) +: frame.times.stages) +
      ("search+shade (format)" -> (t1 - t0) / 1e9) + ("search+shade (float64)" -> (t2 - t1) / 1e9) +
      ("write images" -> (t3 - t2) / 1e9)
    val wall = (System.nanoTime() - wall0) / 1e9
    val searchSecs = (t1 - t0) / 1e9
    val json = ujson.Obj(
      "scene" -> scene, "format" -> fmt.toString, "g" -> g, "width" -> frame.width, "height" -> frame.height,
      "finalGatherRays" -> config.finalGatherRays, "photons" -> hw.stats.photons, "emittedPhotonPaths" -> frame.emittedPaths.toDouble,
      "h" -> frame.h, "hQuantized" -> frame.map.hValue, "hBits" -> fmt.hex(frame.map.h),
      "queries" -> hw.stats.queries.toDouble, "treeSearchOps" -> hw.stats.treeSearchOps.toDouble,
      "shaderOps" -> hw.stats.shaderOps.toDouble, "shaderOpsPassingCond" -> hw.stats.shaderOpsPassing.toDouble,
      "treeDepth" -> hw.stats.treeDepth, "psnrIndirectVsFloat64" -> (if (psnr.isInfinite) ujson.Str("inf") else ujson.Num(psnr)),
      "shaderOpsPerSecond" -> (if (searchSecs > 0) hw.stats.shaderOps / searchSecs else 0.0),
      "searchShadeCpuSeconds" -> searchCpu.map(ujson.Num(_)).getOrElse(ujson.Null),
      "threads" -> threads, "wallSeconds" -> wall,
      "stageSeconds" -> ujson.Obj.from(times.stages.map { case (k, v) => k -> ujson.Num(v) }))
    Files.write(files(4), ujson.write(json, indent = 2).getBytes("UTF-8"))
    if (!quiet) {
      println(s"scene ${config.file} (${frame.width}x${frame.height}, ${config.finalGatherRays} final-gather rays), format $fmt (SOA g = $g), h = ${frame.map.hValue}")
      println(hw.stats.describe)
      println(f"PSNR of the $fmt indirect image against float64: ${if (psnr.isInfinite) "inf" else f"$psnr%.2f dB"}")
      println(times.stages.map { case (k, v) => f"$k $v%.2fs" }.mkString("time: ", ", ", f"; wall $wall%.2fs"))
      files.foreach(f => println(s"wrote $f"))
    }
    Result(frame, hw.rgb, ref.rgb, hw.stats, psnr, times, files, searchCpu)
  }
}
