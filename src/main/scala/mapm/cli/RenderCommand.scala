package mapm.cli

import mapm.pipeline._

import java.nio.file.{Files, Path, Paths}
import mainargs.{ParserForMethods, arg, main}
import mapm.MapmError
import mapm.cli.Args.rtlOptionsParser
import mapm.model.{ImageIO, Metrics, Render, RgbImage, ShadeArith}
import mapm.numerics.{Arith, Vec3}
import mapm.sim.MapmRtl

/** `mapm render`: the main job. Renders a frame through the emitted RTL of a whole MAPM in
  * Verilator and checks it against the model ([[RtlRun]]): every shader operation bit for bit
  * (in the harness, while it runs), the frame bit for bit against the model frame accumulated the
  * same exact way, the TS-op count against the model's; and prints the PSNR against float64.
  *
  * Outputs in `--out`, named after the scene file (`cornell-box-scene-small` for
  * `test-scenes/cornell-box/scene-small.json`): `<scene>-rtl.png` / `.pfm` (direct light plus the
  * RTL's indirect light), `<scene>-rtl-indirect.pfm` (the RTL's result alone),
  * `<scene>-rtl-stats.json` (the harness's stats plus the model's counts, the comparison and
  * timings); `-rtl-timing` in place of `-rtl` for `--fidelity timing`, whose colours are the
  * model's; the run's working files (memory image, expected SOs, the harness's own outputs) in
  * `<scene>-rtl/`. A run stopped by `--max-cycles` is reported as such: its results so far are
  * checked, the unfinished frame is neither compared nor written.
  *
  * It runs the MAPM as its coprocessor ([[mapm.soc.MapmCoproc]], docs/coprocessor.md): the frame is
  * the one the hardware wrote into its frame buffer. `--bare` runs the MAPM alone and the harness
  * adds the colours (every other command's default; `--coproc` there). */
object RenderCommand extends Command {
  val name = "render"
  val summary = "render a frame through the MAPM RTL in Verilator and check it against the model"
  val defaultScene: String = ModelRun.defaultScene

  @main
  def render(
      @arg(doc = "Tree Search Modules") tsm: Int = 16,
      @arg(doc = "Shader Operation Modules") som: Int = 16,
      @arg(doc = "SOAs per SOM") soa: Int = 2,
      @arg(doc = "write an FST waveform to this file (builds a traced harness; --max-cycles, --wave-start and --wave-end keep it short)") wave: Option[String] = None,
      @arg(doc = "first cycle of the waveform") waveStart: Long = 0,
      @arg(doc = "last cycle of the waveform (default: the end of the run)") waveEnd: Option[Long] = None,
      @arg(doc = "the MAPM alone, the harness adding every colour into its pixel (host-side accumulation, docs/harness.md), instead of the coprocessor (the default: it reads its queries, adds the colours and writes the frame buffer itself; docs/coprocessor.md)") bare: mainargs.Flag = mainargs.Flag(),
      options: RtlOptions
  ): Int = {
    val wall0 = System.nanoTime()
    MapmError.check(!(bare.value && options.hw.coproc.value), "render: --bare and --coproc exclude each other (the coprocessor is render's default)")
    val opts = if (bare.value) options else options.copy(hw = options.hw.copy(coproc = mainargs.Flag(true)))
    val wavePath = wave.map(Paths.get(_).toAbsolutePath)
    val harness = opts.harness(wavePath, waveStart, waveEnd.getOrElse(Long.MaxValue))
    val log = (l: String) => System.err.println(s"mapm: $l")
    if ((tsm, som, soa) == (16, 16, 2))
      log("MAPM 16/16/2, the default and the largest configuration (--tsm --som --soa choose another; 1/1/1 builds in about a minute)")
    // The Verilog is emitted and verilated while the model computes the frame and its expected SOs.
    val setup = opts.settings(harness = Some(harness)).setup(Seq((tsm, som, soa)), prebuild = Some((wave.isDefined, opts.simThreads)), log = log)
    val (p, prep) = (setup.params.head, setup.prep)
    val timing = p.sim.fidelity == mapm.params.Fidelity.Timing // colours from the model: nothing to compare
    val f = prep.frame
    println(s"scene ${prep.config.file} (${f.width}x${f.height}, ${prep.config.finalGatherRays} final-gather rays), format ${f.format}, " +
      s"h = ${f.map.hValue}; MAPM ${p.counts.label} (${MapmRtl.topName(p)})")
    println(s"model: queries ${f.querySet.size}, TS ops ${prep.model.tsOps}, shader ops ${prep.model.count} (passing cond ${prep.model.passing})")
    val run = RtlRun.runConfig(prep, p, harness, prep.work, log)
    val stopped = run.stopped // at --max-cycles, as asked: the frame is unfinished
    val compare = !timing && !stopped
    val ref = if (stopped) Array.emptyDoubleArray else RtlRun.reference(prep, opts.threads)
    val rtl = run.outcome.frame.filter(_.length == 3 * f.pixels).filterNot(_ => stopped)
    val psnr = rtl.filter(_ => compare).map(Metrics.psnr(_, ref))
    // The conventional render also gives the online arithmetic's image quality (its model frame).
    val onlinePsnr = if (opts.arith == Arith.Online || stopped) None else Some(Metrics.psnr(
      Render.run(f.map, f.querySet, f.pixels, ShadeArith.hardware(f.format, opts.g), opts.threads).rgb, ref))
    val outDir = Paths.get(opts.out)
    val stem = s"${prep.name}-${if (timing) "rtl-timing" else "rtl"}"
    val files = rtl.toSeq.flatMap(rgb => writeImages(prep, rgb, outDir, stem))
    val stats = outDir.resolve(s"$stem-stats.json")
    val json = ujson.Obj.from(run.outcome.stats.map(_.json.value.toSeq).getOrElse(Seq.empty))
    def dB(v: Double) = if (v.isInfinite) ujson.Str("inf") else ujson.Num(v)
    def seconds(ts: Seq[(String, Double)]) = ujson.Obj.from(ts.map { case (k, v) => k -> ujson.Num(v) })
    json.value ++= Seq("scene" -> ujson.Str(opts.scene), "format" -> ujson.Str(f.format.toString), "g" -> ujson.Num(opts.g),
      "arith" -> ujson.Str(opts.arith.name),
      "configuration" -> ujson.Str(p.counts.label), "width" -> ujson.Num(f.width), "height" -> ujson.Num(f.height),
      "modelTsOps" -> ujson.Num(prep.model.tsOps.toDouble), "modelShaderOps" -> ujson.Num(prep.model.count.toDouble),
      "modelShaderOpsPassingCond" -> ujson.Num(prep.model.passing.toDouble),
      "perSoCheck" -> ujson.Str(run.outcome.verdict), "frameEqualsModel" -> (if (compare) ujson.Bool(run.frameEqual) else ujson.Null),
      "stoppedAtMaxCycles" -> ujson.Bool(stopped),
      "psnrIndirectVsFloat64" -> psnr.map(dB).getOrElse(ujson.Null),
      "psnrOnlineModelVsFloat64" -> onlinePsnr.map(dB).getOrElse(ujson.Null),
      "harnessWallSeconds" -> run.outcome.stats.map(s => ujson.Num(s.wallSeconds)).getOrElse(ujson.Null),
      "stageSeconds" -> seconds(prep.times.stages ++ run.times), "besideModelSeconds" -> seconds(run.beside),
      "wallSeconds" -> ujson.Num((System.nanoTime() - wall0) / 1e9))
    Files.write(stats, ujson.write(json, indent = 2).getBytes("UTF-8"))
    for (s <- run.outcome.stats)
      println(f"RTL: ${s.cycles}%d cycles, SO ${s.soIssued}%d (${s.soPerCycle}%.3f/cycle), passing cond ${s.soPassingCond}%d, " +
        s"TS ops ${s.tsOps.map(v => f"$v%d (${s.tsOpsPerCycle.getOrElse(Double.NaN)}%.3f/cycle)").getOrElse("n/a")}, " +
        f"memory ${s.bytesFetched}%d B (${s.gbPerSecond}%.2f GB/s at ${opts.clockGhz} GHz); simulated ${s.simulatedCyclesPerSecond}%.0f cycles/s")
    println(s"per-SO check: ${run.outcome.verdict}")
    if (stopped) println("frame, TS-op count and PSNR: not compared, and no image written: the run stopped at --max-cycles before the frame was done")
    else if (timing) println("frame: not checked: the SOAs were their timing model, so the colours (and the image, and its PSNR) are the model's")
    else println(s"frame against the model frame: ${if (run.frameEqual) "bit-equal" else run.frameDiff.getOrElse("")}")
    run.tsOpsEqual.filterNot(_ => stopped).foreach(e => println(s"TS ops against the model: ${if (e) "equal" else "DIFFERENT"}"))
    def dBText(v: Double) = if (v.isInfinite) "inf" else f"$v%.2f dB"
    psnr.foreach(v => println(s"PSNR of the RTL indirect image (${opts.arith} arithmetic) against float64: ${dBText(v)}"))
    onlinePsnr.foreach(v => println(s"PSNR of the online arithmetic's indirect image (model, g = ${opts.g}) against float64: ${dBText(v)}"))
    def list(ts: Seq[(String, Double)]) = ts.map { case (k, v) => f"$k $v%.2fs" }.mkString(", ")
    println(s"time: ${list(prep.times.stages ++ run.times)}" + (if (run.beside.isEmpty) "" else s" (beside the model: ${list(run.beside)})") +
      f"; wall ${(System.nanoTime() - wall0) / 1e9}%.2fs")
    wavePath.filter(Files.isRegularFile(_)).foreach(w =>
      println(s"wrote $w (FST waveform of cycles $waveStart to ${waveEnd.fold("the end")(_.toString)}; open it with gtkwave)"))
    (files :+ stats).foreach(x => println(s"wrote $x"))
    if (!run.passed && !stopped) MapmError.fail(s"render: ${run.failure} (files in ${prep.work})")
    0
  }

  /** `<stem>.png` / `.pfm` (direct + RTL indirect) and `<stem>-indirect.pfm`. */
  def writeImages(prep: RtlRun.Prepared, rgb: Array[Double], outDir: Path, stem: String): Seq[Path] = {
    val f = prep.frame
    def image(withDirect: Boolean) = RgbImage(f.width, f.height, Array.tabulate(f.pixels) { i =>
      val ind = Vec3(rgb(3 * i), rgb(3 * i + 1), rgb(3 * i + 2))
      if (withDirect) ind + f.direct(i) else ind
    })
    val files = Seq(outDir.resolve(s"$stem.png"), outDir.resolve(s"$stem.pfm"), outDir.resolve(s"$stem-indirect.pfm"))
    val full = image(withDirect = true)
    ImageIO.writePng(files(0), full); ImageIO.writePfm(files(1), full); ImageIO.writePfm(files(2), image(withDirect = false))
    files
  }

  lazy val parser: ParserForMethods[_] = ParserForMethods(this)

  def run(args: Seq[String]): Int = Args.run(this, args)
}
