package mapm.pipeline

import java.nio.file.{Files, Path, Paths}

import mapm.MapmError
import mapm.format.{MemoryImage, SlotLayout}
import mapm.model._
import mapm.numerics._
import mapm.sim.{ExpectedSo, Harness, MapmRtl}
import mapm.params.{Fidelity, MapmParams}
import mapm.pipeline.Tuning
import scala.concurrent.{Await, Future}
import scala.concurrent.duration.Duration

/** The RTL render shared by `render` and `sweep`: scene -> model ([[Frame]]) -> memory image and
  * expected SOs (the model in the hardware's arithmetic) -> emitted Verilog (cached) -> Verilator
  * harness (cached) -> run -> comparison with the model. */
object RtlRun {
  /** A frame ready for the hardware: its files in `work` and the model's results. */
  final case class Prepared(name: String, config: SceneConfig, frame: Frame, layout: SlotLayout, image: Path, expected: Path,
                            model: ExpectedSo.Result, work: Path, times: StageTimes, arith: Arith = Arith.Online,
                            builds: Map[MapmParams, Future[Built]] = Map.empty)

  /** A configuration's harness, emitted and built (with its trace flag and model threads), and the seconds each took. */
  final case class Built(exe: Path, trace: Boolean, simThreads: Int, emitSeconds: Double, buildSeconds: Double)

  /** Emits and builds `p`'s harness ([[MapmRtl.emit]], [[Harness.build]]; `fresh` as there). */
  def build(p: MapmParams, trace: Boolean, simThreads: Int, log: String => Unit, fresh: Boolean = false): Built = {
    val t0 = System.nanoTime()
    val (sv, top) = MapmRtl.emit(p, log)
    val t1 = System.nanoTime()
    val exe = Harness.build(sv, top, trace, log, simThreads, fresh)
    Built(exe, trace, simThreads, (t1 - t0) / 1e9, secs(t1))
  }

  /** The configurations to run and the frame they run on, in one number format. */
  final case class Setup(params: Seq[MapmParams], prep: Prepared)

  /** One configuration's run: the harness outcome, whether the frame equals the model's bit for
    * bit (and the first differing value), and seconds per stage: `times` one after the other on
    * the way to the result, `beside` those that ran on other threads while the model worked (the
    * emit and build of a configuration prepared early; `times` then holds the wait for them). */
  final case class ConfigRun(p: MapmParams, outcome: Harness.Outcome, frameEqual: Boolean, frameDiff: Option[String],
                             tsOpsEqual: Option[Boolean], times: Seq[(String, Double)], beside: Seq[(String, Double)] = Seq.empty) {
    def passed: Boolean = outcome.passed && frameEqual && !tsOpsEqual.contains(false)
    /** Ended at `--max-cycles` as asked, every result that came out checked: the frame and the
      * TS-op count are unfinished, so not compared. */
    def stopped: Boolean = outcome.stopped
    /** Why it failed, in one line. */
    def failure: String =
      if (!outcome.passed) outcome.verdict
      else if (!frameEqual) s"the RTL frame differs from the model frame: ${frameDiff.getOrElse("")}"
      else s"TS-op count ${outcome.stats.flatMap(_.tsOps).getOrElse(0L)} differs from the model's"
  }

  private def secs(t0: Long): Double = (System.nanoTime() - t0) / 1e9

  /** The name of a frame's files: the scene's, with `-conv` for the conventional arithmetic. */
  def frameName(scene: String, arith: Arith): String =
    ModelRun.sceneName(Paths.get(scene)) + (if (arith == Arith.Online) "" else "-conv")

  /** The folder of a frame's files under `outDir`: `<frame name>-rtl`. */
  def workDir(scene: String, arith: Arith, outDir: String): Path = Paths.get(outDir).resolve(s"${frameName(scene, arith)}-rtl")

  /** Loads `scene`, resolves its number format once (`format`, else the scene's, else fp32), makes
    * the configurations `configs` (TSM/SOM/SOA) in it with `g` guard digits, arithmetic `arith`
    * and memory records in `layout`, sized by `tuning`, then runs the model side once; files go to
    * `outDir/<scene>-rtl/` (`<scene>-conv-rtl/` for the conventional arithmetic, whose name
    * carries `-conv` in every output file). With `prebuild` (trace, model threads) every
    * configuration is emitted and built on a thread of its own while the model runs, and
    * [[runConfig]] takes that build. The host writes the query records in `queryOrder`, the order it
    * runs them in: query k of the image, of its stream (the identity) and of the expected SOs is
    * query `queryOrder.of(...)(k)` of the frame, and the coprocessor runs the records in array order
    * without reading a stream (docs/coprocessor.md, QUERY_ORDER). */
  def setup(scene: String, format: Option[FloatFormat], g: Int, configs: Seq[(Int, Int, Int)], outDir: String, threads: Int,
            layout: SlotLayout = SlotLayout.Packed, arith: Arith = Arith.Online, fidelity: Fidelity = Fidelity.Full,
            tuning: Tuning = Tuning(), prebuild: Option[(Boolean, Int)] = None, log: String => Unit = _ => (),
            queryOrder: QueryOrder = QueryOrder.Host): Setup = {
    MapmError.check(threads >= 1, s"--threads must be at least 1, got $threads")
    val (config, fmt, params) = configure(scene, format, g, configs, layout, arith, fidelity, tuning)
    import scala.concurrent.ExecutionContext.Implicits.global
    val builds = prebuild.toSeq.flatMap { case (trace, threads) => params.map(p => p -> Future(build(p, trace, threads, log))) }.toMap
    val frame = Frame.prepare(config, fmt, threads)
    val name = frameName(scene, arith)
    val work = workDir(scene, arith, outDir)
    Files.createDirectories(work)
    val t0 = System.nanoTime()
    val image = work.resolve("image.bin")
    val queries = frame.querySet.permuted(queryOrder.of(frame.querySet))
    mapm.sim.FrameImage.of(frame.map, queries, layout).write(image)
    val t1 = System.nanoTime()
    val expected = work.resolve("expected.bin")
    val model = ExpectedSo.write(frame.map, queries, g, frame.width, frame.height, expected, threads, Some("model SOs"), arith,
      coproc = tuning.coproc)
    Setup(params, Prepared(name, config, frame, layout, image, expected, model, work,
      frame.times + ("memory image" -> (t1 - t0) / 1e9) + ("model SOs" -> secs(t1)), arith, builds))
  }

  /** The scene loaded, its format resolved and the configurations made and checked against it
    * ([[checkFits]]): everything [[setup]] checks before the model runs, without running it. */
  def configure(scene: String, format: Option[FloatFormat], g: Int, configs: Seq[(Int, Int, Int)], layout: SlotLayout,
                arith: Arith, fidelity: Fidelity, tuning: Tuning): (SceneConfig, FloatFormat, Seq[MapmParams]) = {
    val config = ModelRun.loadScene(scene)
    val fmt = format.orElse(config.format).getOrElse(FloatFormat.fp32)
    val params = configs.map { case (t, s, a) => Configure.of(t, s, a, fmt, g, layout, arith, fidelity, tuning) }
    checkFits(config, params.headOption.getOrElse(MapmParams.default).indices)
    params.foreach(MapmRtl.checkEmittable(_))
    (config, fmt, params)
  }

  /** Fails, before any work, when the scene can need more query points or photons than the
    * hardware's indices count (`width x height x finalGatherRays` is the most query points a frame
    * can have; the photon tree has one node per photon). */
  def checkFits(config: SceneConfig, ix: mapm.params.IndexParams): Unit = {
    val queries = config.width.toLong * config.height * config.finalGatherRays
    MapmError.check(queries <= (1L << ix.queryBits), s"${config.file}: up to $queries query points (width x height x finalGatherRays) " +
      s"exceed the hardware's ${ix.queryBits}-bit query index (at most ${1L << ix.queryBits})")
    MapmError.check(config.photons.toLong <= (1L << ix.nodeBits), s"${config.file}: ${config.photons} photons exceed the hardware's " +
      s"${ix.nodeBits}-bit node index (at most ${1L << ix.nodeBits} photons)")
  }

  /** The frame of [[setup]] alone, for callers that make their own configurations in its format. */
  def prepare(scene: String, format: Option[FloatFormat], g: Int, outDir: String, threads: Int,
              layout: SlotLayout = SlotLayout.Packed, arith: Arith = Arith.Online, coproc: Boolean = false): Prepared =
    setup(scene, format, g, Seq.empty, outDir, threads, layout, arith, tuning = Tuning(coproc = coproc)).prep

  /** Emits, builds and runs configuration `p` (in the frame's format, as [[setup]] makes it) on a
    * prepared frame; the harness writes into `dir` (with a progress bar when `progress`). */
  def runConfig(prep: Prepared, p: MapmParams, opts: Harness.RunOptions, dir: Path, log: String => Unit, progress: Boolean = true): ConfigRun = {
    MapmError.check(p.numbers.format == prep.frame.format && p.memory.layout == prep.layout && p.numbers.arith == prep.arith,
      s"${p.name}: the frame was prepared in ${prep.frame.format} ${prep.arith} with the ${prep.layout} layout, the configuration reads ${p.numbers.format} ${p.numbers.arith} in the ${p.memory.layout} one")
    val t0 = System.nanoTime()
    val early = prep.builds.get(p).map(f => Await.result(f, Duration.Inf)).filter(b => b.trace == opts.wave.isDefined && b.simThreads == opts.simThreads)
    val built = early.getOrElse(build(p, opts.wave.isDefined, opts.simThreads, log))
    val t2 = System.nanoTime()
    // The coprocessor's pass takes the frame scale the model chose for the frame (docs/coprocessor.md).
    MapmError.check(!p.sim.coproc || prep.model.coproc.isDefined, s"${p.name}: the frame was prepared without the coprocessor's model frame (prepare it with coproc)")
    val runOpts = if (p.sim.coproc) opts.copy(frameScale = prep.model.coproc.map(_.scale)) else opts
    if (p.sim.coproc) MapmError.check(p.frameAccum == mapm.numerics.FrameAccum.default(p.numbers.format),
      s"${p.name}: the model frame is made with the default frame accumulator, this configuration has ${p.frameAccum}")
    val outcome = Harness.run(built.exe, prep.image, prep.expected, dir, runOpts, if (progress) Some(s"RTL ${p.counts.label}") else None)
    val builds = Seq("emit" -> built.emitSeconds, "verilator build" -> built.buildSeconds)
    val (times, beside) =
      if (early.isDefined) (Seq("waiting for the build" -> (t2 - t0) / 1e9, "simulation" -> secs(t2)), builds)
      else (builds :+ ("simulation" -> secs(t2)), Seq.empty)
    val model = if (p.sim.coproc) prep.model.coproc.get.frame else prep.model.frame
    val timingCoproc = p.sim.coproc && p.sim.fidelity == mapm.params.Fidelity.Timing
    val diff = outcome.frame match {
      case None if timingCoproc => None // the SOAs' timing model computes no colour: the frame is the model's
      case None => Some("the harness wrote no frame")
      case Some(f) if f.length != model.length => Some(s"${f.length} values against the model's ${model.length}")
      case Some(f) =>
        model.indices.find(i => java.lang.Double.doubleToRawLongBits(f(i)) != java.lang.Double.doubleToRawLongBits(model(i)))
          .map(i => s"first at pixel ${i / 3} channel ${i % 3}: RTL ${f(i)}, model ${model(i)}")
    }
    val tsOps = outcome.stats.flatMap(_.tsOps).map(_ == prep.model.tsOps)
    ConfigRun(p, outcome, diff.isEmpty, diff, tsOps, times, beside)
  }

  /** The float64 reference of the indirect light (for the PSNR). */
  def reference(prep: Prepared, threads: Int): Array[Double] = {
    val f = prep.frame
    val refMap = PhotonMap.fromTree(f.map.tree, f.photons, FloatFormat.fp64, f.h)
    Render.run(refMap, QuerySet.build(f.queries, FloatFormat.fp64, None), f.pixels, ShadeArith.float64, threads).rgb
  }
}
