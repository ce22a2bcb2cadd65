package mapm.cli

import java.nio.file.{Files, Path, Paths}
import mainargs.{ParserForMethods, arg, main}
import mapm.MapmError
import mapm.cli.Args.rtlOptionsParser
import mapm.model.{Arith, ImageIO, Metrics, Render, RgbImage, ShadeArith, Vec3}
import mapm.sim.MapmRtl

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
      @arg(doc = "Tree Search Modules") tsm: Int = 16,
      @arg(doc = "Shader Operation Modules") som: Int = 16,
      @arg(doc = "SOAs per SOM") soa: Int = 2,
      @arg(doc = "write an FST waveform to this file (builds a traced harness)") wave: Option[String] = None,
      @arg(doc = "first cycle of the waveform") waveStart: Long = 0,
      @arg(doc = "last cycle of the waveform") waveEnd: Long = Long.MaxValue,
      opts: RtlOptions
  ): Int = {
    val wall0 = System.nanoTime()
    val harness = opts.harness(wave.map(Paths.get(_).toAbsolutePath), waveStart, waveEnd)
    val log = (l: String) => System.err.println(s"mapm: $l")
    // The Verilog is emitted and verilated while the model computes the frame and its expected SOs.
    val setup = opts.setup(Seq((tsm, som, soa)), prebuild = Some((wave.isDefined, opts.simThreads)), log = log)
    val (p, prep) = (setup.params.head, setup.prep)
    val timing = p.sim.fidelity == mapm.params.Fidelity.Timing // colours from the model: nothing to compare
    val f = prep.frame
    println(s"scene ${prep.config.file} (${f.width}x${f.height}, ${prep.config.finalGatherRays} final-gather rays), format ${f.format}, " +
      s"h = ${f.map.hValue}; MAPM ${p.counts.label} (${MapmRtl.topName(p)})")
    println(s"model: queries ${f.querySet.size}, TS ops ${prep.model.tsOps}, shader ops ${prep.model.count} (passing cond ${prep.model.passing})")
    val run = RtlRun.runConfig(prep, p, harness, prep.work, log)
    val ref = RtlRun.reference(prep, opts.threads)
    val rtl = run.outcome.frame.filter(_.length == 3 * f.pixels)
    val psnr = rtl.map(Metrics.psnr(_, ref))
    // The conventional render also gives the online arithmetic's image quality (its model frame).
    val onlinePsnr = if (opts.arith == Arith.Online) None else Some(Metrics.psnr(
      Render.run(f.map, f.querySet, f.pixels, ShadeArith.hardware(f.format, opts.g), opts.threads).rgb, ref))
    val outDir = Paths.get(opts.out)
    val files = rtl.toSeq.flatMap(rgb => writeImages(prep, rgb, outDir))
    val stats = outDir.resolve(s"${prep.name}-rtl-stats.json")
    val json = ujson.Obj.from(run.outcome.stats.map(_.json.value.toSeq).getOrElse(Seq.empty))
    def dB(v: Double) = if (v.isInfinite) ujson.Str("inf") else ujson.Num(v)
    json.value ++= Seq("scene" -> ujson.Str(opts.scene), "format" -> ujson.Str(f.format.toString), "g" -> ujson.Num(opts.g),
      "arith" -> ujson.Str(opts.arith.name),
      "config" -> ujson.Str(p.counts.label), "width" -> ujson.Num(f.width), "height" -> ujson.Num(f.height),
      "modelTsOps" -> ujson.Num(prep.model.tsOps.toDouble), "modelShaderOps" -> ujson.Num(prep.model.count.toDouble),
      "modelShaderOpsPassingCond" -> ujson.Num(prep.model.passing.toDouble),
      "perSoCheck" -> ujson.Str(run.outcome.verdict), "frameEqualsModel" -> (if (timing) ujson.Null else ujson.Bool(run.frameEqual)),
      "psnrIndirectVsFloat64" -> psnr.filterNot(_ => timing).map(dB).getOrElse(ujson.Null),
      "psnrOnlineModelVsFloat64" -> onlinePsnr.map(dB).getOrElse(ujson.Null),
      "harnessWallSeconds" -> run.outcome.stats.map(s => ujson.Num(s.wallSeconds)).getOrElse(ujson.Null),
      "stageSeconds" -> ujson.Obj.from((prep.times.stages ++ run.times).map { case (k, v) => k -> ujson.Num(v) }),
      "wallSeconds" -> ujson.Num((System.nanoTime() - wall0) / 1e9))
    Files.write(stats, ujson.write(json, indent = 2).getBytes("UTF-8"))
    for (s <- run.outcome.stats)
      println(f"RTL: ${s.cycles}%d cycles, SO ${s.soIssued}%d (${s.soPerCycle}%.3f/cycle), passing cond ${s.soPassingCond}%d, " +
        s"TS ops ${s.tsOps.map(v => f"$v%d (${s.tsOpsPerCycle.getOrElse(Double.NaN)}%.3f/cycle)").getOrElse("n/a")}, " +
        f"memory ${s.bytesFetched}%d B (${s.gbPerSecond}%.2f GB/s at ${opts.clockGhz} GHz); simulated ${s.simulatedCyclesPerSecond}%.0f cycles/s")
    println(s"per-SO check: ${run.outcome.verdict}")
    if (timing) println("frame: not checked: the SOAs were their timing model, so the colours (and the image, and its PSNR) are the model's")
    else println(s"frame against the model frame: ${if (run.frameEqual) "bit-equal" else run.frameDiff.getOrElse("")}")
    run.tsOpsEqual.foreach(e => println(s"TS ops against the model: ${if (e) "equal" else "DIFFERENT"}"))
    def dBText(v: Double) = if (v.isInfinite) "inf" else f"$v%.2f dB"
    psnr.filterNot(_ => timing).foreach(v => println(s"PSNR of the RTL indirect image (${opts.arith} arithmetic) against float64: ${dBText(v)}"))
    onlinePsnr.foreach(v => println(s"PSNR of the online arithmetic's indirect image (model, g = ${opts.g}) against float64: ${dBText(v)}"))
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
