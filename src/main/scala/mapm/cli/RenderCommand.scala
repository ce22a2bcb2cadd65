package mapm.cli

import java.nio.file.{Files, Path, Paths}
import mainargs.{ParserForMethods, arg, main}
import mapm.MapmError
import mapm.model.{FloatFormat, ImageIO, Metrics, Parallel, RgbImage, Vec3}
import mapm.sim.{Harness, MapmRtl}
import mapm.params.MapmParams
import Args.FloatFormatReader

/** `mapm render`: the main job. Renders a frame through the emitted RTL of a whole MAPM in
  * Verilator and checks it against the model ([[RtlRun]]): every shader operation bit for bit
  * (in the harness, while it runs), the frame bit for bit against the model frame accumulated the
  * same exact way, the TS-op count against the model's; and prints the PSNR against float64.
  *
  * Outputs in `--out`: `<scene>-rtl.png` / `.pfm` (direct light plus the RTL's indirect light),
  * `<scene>-rtl-indirect.pfm` (the RTL's result alone), `<scene>-rtl-stats.json` (the harness's
  * stats plus the model's counts, the comparison and timings); the run's working files (memory
  * image, expected SOs, the harness's own outputs) in `<scene>-rtl/`. */
object RenderCommand extends Command {
  val name = "render"
  val summary = "render a frame through the MAPM RTL in Verilator and check it against the model"
  val defaultScene = "test-scenes/cornell-box/scene.json"

  @main
  def render(
      @arg(doc = "scene description file (JSON)") scene: String = defaultScene,
      @arg(doc = "Tree Search Modules") tsm: Int = 16,
      @arg(doc = "Shader Operation Modules") som: Int = 16,
      @arg(doc = "SOAs per SOM") soa: Int = 2,
      @arg(doc = "number format: fp32, bf16, fp16, fp24 or E,M (default: the scene's, else fp32)") format: Option[FloatFormat] = None,
      @arg(name = "g", doc = "guard digits of the SOA's online units") g: Int = 3,
      @arg(doc = "memory latency in cycles") latency: Int = 100,
      @arg(doc = "draw each request's latency from [latency, this] (0: fixed latency)") latencyMax: Int = 0,
      @arg(doc = "probability of a gap in the query stream each cycle") queryGap: Double = 0,
      @arg(doc = "probability that the memory refuses a request each cycle") reqStall: Double = 0,
      @arg(doc = "probability that the memory holds back a ready response beat") respGap: Double = 0,
      @arg(doc = "memory bandwidth in bytes per cycle") bandwidth: Double = 14.0,
      @arg(doc = "clock for the GB/s figure, in GHz") clockGhz: Double = 1.5,
      @arg(doc = "seed of the memory's response reordering") seed: Long = 1,
      @arg(doc = "threads of the Verilator model (a separate build; 1 is fastest on this design, see docs/harness.md)") simThreads: Int = 1,
      @arg(doc = "stop with FAIL after this many cycles (0: no limit)") maxCycles: Long = 0,
      @arg(doc = "write an FST waveform to this file (builds a traced harness)") wave: Option[String] = None,
      @arg(doc = "first cycle of the waveform") waveStart: Long = 0,
      @arg(doc = "last cycle of the waveform") waveEnd: Long = Long.MaxValue,
      @arg(doc = "output folder") out: String = "out",
      @arg(doc = "worker threads of the model") threads: Int = Parallel.defaultThreads
  ): Int = {
    val wall0 = System.nanoTime()
    val opts = Harness.RunOptions(latency, bandwidth, seed, maxCycles, clockGhz, wave.map(Paths.get(_).toAbsolutePath), waveStart, waveEnd,
      latencyMax, queryGap, reqStall, respGap, simThreads)
    val fmt0 = format.orElse(ModelRun.loadScene(scene).format).getOrElse(FloatFormat.fp32)
    val p = MapmParams.of(tsm, som, soa, fmt0, g)
    val prep = RtlRun.prepare(scene, Some(fmt0), g, out, threads)
    val f = prep.frame
    println(s"scene ${prep.config.file} (${f.width}x${f.height}, ${prep.config.finalGatherRays} final-gather rays), format ${f.format}, " +
      s"h = ${f.map.hValue}; MAPM ${p.counts.label} (${MapmRtl.topName(p)})")
    println(s"model: queries ${f.querySet.size}, TS ops ${prep.model.tsOps}, shader ops ${prep.model.count} (passing cond ${prep.model.passing})")
    val run = RtlRun.runConfig(prep, p, opts, prep.work, l => System.err.println(s"mapm: $l"))
    val ref = RtlRun.reference(prep, threads)
    val rtl = run.outcome.frame.filter(_.length == 3 * f.pixels)
    val psnr = rtl.map(Metrics.psnr(_, ref))
    val outDir = Paths.get(out)
    val files = rtl.toSeq.flatMap(rgb => writeImages(prep, rgb, outDir))
    val stats = outDir.resolve(s"${prep.name}-rtl-stats.json")
    val json = ujson.Obj.from(run.outcome.stats.map(_.obj.toSeq).getOrElse(Seq.empty))
    json.value ++= Seq("scene" -> ujson.Str(scene), "format" -> ujson.Str(f.format.toString), "g" -> ujson.Num(g),
      "config" -> ujson.Str(p.counts.label), "width" -> ujson.Num(f.width), "height" -> ujson.Num(f.height),
      "modelTsOps" -> ujson.Num(prep.model.tsOps.toDouble), "modelShaderOps" -> ujson.Num(prep.model.count.toDouble),
      "modelShaderOpsPassingCond" -> ujson.Num(prep.model.passing.toDouble),
      "perSoCheck" -> ujson.Str(run.outcome.verdict), "frameEqualsModel" -> ujson.Bool(run.frameEqual),
      "psnrIndirectVsFloat64" -> psnr.map(v => if (v.isInfinite) ujson.Str("inf") else ujson.Num(v)).getOrElse(ujson.Null),
      "harnessWallSeconds" -> run.outcome.stats.flatMap(_.obj.get("wallSeconds")).getOrElse(ujson.Null),
      "stageSeconds" -> ujson.Obj.from((prep.times.stages ++ run.times).map { case (k, v) => k -> ujson.Num(v) }),
      "wallSeconds" -> ujson.Num((System.nanoTime() - wall0) / 1e9))
    Files.write(stats, ujson.write(json, indent = 2).getBytes("UTF-8"))
    for (s <- run.outcome.stats) {
      def n(k: String) = s.obj.get(k).flatMap(_.numOpt).getOrElse(Double.NaN)
      println(f"RTL: ${n("cycles")}%.0f cycles, SO ${n("soIssued")}%.0f (${n("soPerCycle")}%.3f/cycle), passing cond ${n("soPassingCond")}%.0f, " +
        s"TS ops ${s.obj.get("tsOps").flatMap(_.numOpt).map(v => f"$v%.0f (${n("tsOpsPerCycle")}%.3f/cycle)").getOrElse("n/a")}, " +
        f"memory ${n("bytesFetched")}%.0f B (${n("gbPerSecond")}%.2f GB/s at $clockGhz GHz); simulated ${n("simulatedCyclesPerSecond")}%.0f cycles/s")
    }
    println(s"per-SO check: ${run.outcome.verdict}")
    println(s"frame against the model frame: ${if (run.frameEqual) "bit-equal" else run.frameDiff.getOrElse("")}")
    run.tsOpsEqual.foreach(e => println(s"TS ops against the model: ${if (e) "equal" else "DIFFERENT"}"))
    psnr.foreach(v => println(f"PSNR of the RTL indirect image against float64: ${if (v.isInfinite) "inf" else f"$v%.2f dB"}"))
    println((prep.times.stages ++ run.times).map { case (k, v) => f"$k $v%.2fs" }.mkString("time: ", ", ", f"; wall ${(System.nanoTime() - wall0) / 1e9}%.2fs"))
    (files :+ stats).foreach(x => println(s"wrote $x"))
    if (!run.passed) MapmError.fail(s"render: ${run.failure} (files in ${prep.work})")
    0
  }

  /** `<scene>-rtl.png` / `.pfm` (direct + RTL indirect) and `<scene>-rtl-indirect.pfm`. */
  def writeImages(prep: RtlRun.Prepared, rgb: Array[Double], outDir: Path): Seq[Path] = {
    val f = prep.frame
    def image(withDirect: Boolean) = RgbImage(f.width, f.height, Array.tabulate(f.pixels) { i =>
      val ind = Vec3(rgb(3 * i), rgb(3 * i + 1), rgb(3 * i + 2))
      if (withDirect) ind + f.direct(i) else ind
    })
    val files = Seq(outDir.resolve(s"${prep.name}-rtl.png"), outDir.resolve(s"${prep.name}-rtl.pfm"), outDir.resolve(s"${prep.name}-rtl-indirect.pfm"))
    val full = image(withDirect = true)
    ImageIO.writePng(files(0), full); ImageIO.writePfm(files(1), full); ImageIO.writePfm(files(2), image(withDirect = false))
    files
  }

  def run(args: Seq[String]): Int = Args.run(ParserForMethods(this), args, name)
}
