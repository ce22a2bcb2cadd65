package mapm.sim

import java.nio.charset.StandardCharsets.UTF_8
import java.nio.file.{Files, Path, Paths}

import mapm.MapmError
import mapm.format.CHeader
import scala.jdk.CollectionConverters._
import scala.sys.process._

/** Builds and runs the whole-MAPM Verilator harness (tools/harness, docs/harness.md).
  *
  * [[build]] verilates a directory of emitted SystemVerilog together with the harness sources,
  * the configuration's `mapm_config.h` from that directory (the top's class, port accessors and
  * counters, generated from the parameters) and the generated `mapm_formats.h` (the file records,
  * [[CHeader.formats]]). Builds are kept in the [[BuildCache]] (kind `harness`), keyed by the
  * Verilog, the harness sources, both headers, the flags and the tools' versions, so a changed
  * configuration rebuilds only itself and every spec, command and checkout shares the build. [[run]] starts the harness, turns its `progress` lines into a progress
  * bar and returns its verdict and stats.
  */
object Harness {
  /** The project root: the nearest directory at or above the working directory holding tools/harness/main.cpp. */
  def root: Path = {
    val start = Paths.get("").toAbsolutePath
    Iterator.iterate(start)(_.getParent).takeWhile(_ != null)
      .find(d => Files.isRegularFile(d.resolve("tools/harness/main.cpp")))
      .getOrElse(MapmError.fail(s"tools/harness/main.cpp not found at or above $start (run from the mapm checkout)"))
  }

  def sourceDir: Path = root.resolve("tools/harness")
  /** The coprocessor's C driver (its harness includes it). */
  def driverDir: Path = root.resolve("tools/driver")
  /** The driver's example (docs/examples/mapm_run_frame.c), which the coprocessor's harness runs. */
  def exampleDir: Path = root.resolve("docs/examples")

  private def sources: Seq[Path] =
    Files.list(sourceDir).iterator.asScala.filter(p => p.toString.endsWith(".cpp") || p.toString.endsWith(".h")).toSeq.sortBy(_.toString)

  /** The SystemVerilog files of an emitted design, in name order. */
  def svFiles(dir: Path): Seq[Path] = {
    MapmError.check(Files.isDirectory(dir), s"$dir: no emitted Verilog there")
    val fs = Files.list(dir).iterator.asScala.filter(p => p.toString.endsWith(".sv") || p.toString.endsWith(".v")).toSeq.sortBy(_.toString)
    MapmError.check(fs.nonEmpty, s"$dir: no .sv files")
    fs
  }

  /** Builds (or finds in the cache) the harness for the emitted design in `svDir` whose top module
    * is `top`; `svDir` holds its `mapm_config.h` ([[mapm.sim.HarnessHeader]], as
    * [[MapmRtl.emit]] and `mapm emit` write it). `trace` builds the FST-waveform variant,
    * `threads` > 1 a multithreaded model (Verilator `--threads`). `fresh` builds from scratch
    * without ccache, replacing any cached build (for measuring the build). Returns the executable. */
  def build(svDir: Path, top: String, trace: Boolean = false, log: String => Unit = _ => (), threads: Int = 1,
            fresh: Boolean = false): Path = {
    MapmError.check(threads >= 1 && threads <= 64, s"simulation threads must be 1..64, got $threads")
    val svs = svFiles(svDir)
    val svTexts = svs.map(f => new String(Files.readAllBytes(f), UTF_8)) // read once: tens of MB at 16/16/2
    MapmError.check(svTexts.exists(_.contains(s"module $top")), s"$svDir: no file defines module $top")
    val configFile = svDir.resolve("mapm_config.h")
    MapmError.check(Files.isRegularFile(configFile), s"$svDir: no mapm_config.h (MapmRtl.emit and `mapm emit` write it beside the Verilog)")
    val configHeader = new String(Files.readAllBytes(configFile), UTF_8)
    MapmError.check(configHeader.contains(s"#define MAPM_TOP_NAME \"$top\""), s"$configFile is not the header of $top")
    val formats = CHeader.formats
    val coproc = configHeader.contains("#define MAPM_COPROC 1")
    val regs = mapm.format.RegisterMap.cHeader
    val driver = Seq("mapm_driver.h", "mapm_driver.c").map(driverDir.resolve) :+ exampleDir.resolve("mapm_run_frame.c")
    val vlt = noInlineConfig(svTexts.mkString("\n"))
    val designFlags = if (configHeader.contains("#define MAPM_FIDELITY_TIMING 1")) timingFlags else Seq.empty
    val inputs = svs.zip(svTexts).map { case (f, t) => f.getFileName.toString + t } ++
      (sources ++ driver).map(f => f.getFileName.toString + new String(Files.readAllBytes(f), UTF_8)) :+ configHeader :+ formats :+ regs :+ vlt :+
      s"trace=$trace threads=$threads" :+ (Verilator.harnessOptFlags ++ designFlags).mkString(" ")
    val name = s"$top${if (trace) "-fst" else ""}${if (threads > 1) s"-t$threads" else ""}"
    val t0 = System.nanoTime()
    var built = false
    // Built in a private folder and renamed into place under the cache's lock: concurrent builds
    // of one configuration (local jobs, Slurm array tasks, parallel specs) build it once.
    val dir = BuildCache.entry("harness", name, inputs, d => Files.isExecutable(d.resolve("harness")), rebuild = fresh) { tmp =>
      built = true
      log(s"verilating $top into ${BuildCache.root.resolve("harness")} (cached for later runs) ...")
      // Both headers beside the build (not -I of the emit folder), so that every path the compiler
      // sees is the same for every configuration and ccache shares the run-time library's objects.
      Files.write(tmp.resolve("mapm_formats.h"), formats.getBytes(UTF_8))
      Files.write(tmp.resolve("mapm_config.h"), configHeader.getBytes(UTF_8))
      Files.write(tmp.resolve("mapm_regs.h"), regs.getBytes(UTF_8))
      val fileList = tmp.resolve("files.f")
      val config = tmp.resolve("no-inline.vlt")
      Files.write(config, vlt.getBytes(UTF_8))
      Files.write(fileList, (config +: svs).map(_.toAbsolutePath.toString).mkString("\n").getBytes(UTF_8))
      val flags = designFlags ++ Seq("-f", fileList.toString, "-CFLAGS", s"-I${sourceDir.toAbsolutePath} -I${driverDir.toAbsolutePath} -I${exampleDir.toAbsolutePath} -I${tmp.toAbsolutePath} -std=c++17") ++
        (if (trace) Seq("--trace-fst") else Seq.empty) ++ (if (threads > 1) Seq("--threads", threads.toString) else Seq.empty)
      val main = sourceDir.resolve(if (coproc) "coproc.cpp" else "main.cpp").toAbsolutePath
      Verilator.build(Seq.empty, main, top, tmp, "harness", flags, ccache = !fresh, log = log, opt = Verilator.harnessOptFlags)
    }
    if (built) log(f"built in ${(System.nanoTime() - t0) / 1e9}%.1f s")
    dir.resolve("harness")
  }

  /** Verilator flags of a design in timing fidelity. Its SOAs read no photon data, so each SOP L1
    * data memory is written but never read, and Verilator 5.006 then "localizes" it: the
    * 1,024 x 256-bit array becomes a local of the per-cycle function, zeroed (VL_ZERO_W) on every
    * call: 63 % of the time at 2/2/2 (perf), more with more SOMs. `-fno-localize` keeps it a
    * member: the 2/2/2 Cornell frame ran 4.2 times as fast
    * (25,400 against 107,000 cycles/s, same 2,889,311 cycles). Not used in full fidelity, where it
    * cost 6 % more instructions per cycle at 2/1/2 (0.162 M against 0.153 M, bench-sim). */
  val timingFlags: Seq[String] = Seq("-fno-localize")

  /** Modules Verilator must keep as their own classes rather than inline: the replicated units,
    * SOA and TSA (and their conventional counterparts ConvSOA, ConvTSA), and the TSM and SOM that
    * hold them with their L1 caches and queues. Inlined, the 32 SOAs of 16/16/2 become 130 MB of C++
    * that take 9 minutes to compile and simulate at half the speed of one shared class (measured
    * on 32 fp32 SOAs: 3.9 k against 7.8 k cycles per second, 1 minute to build). Keeping the TSMs
    * and SOMs too cut the 16/16/2 build from 293 s to 220 s and its C++ from 60 to 49 MB, and ran
    * 7 % faster (docs/harness.md, "Speed"). */
  def noInlineConfig(sv: String): String = {
    val names = """(?m)^module\s+((?:Conv)?(?:SOA|TSA)_\w+|Tsm_\w+|Som_\w+)""".r.findAllMatchIn(sv).map(_.group(1)).toSeq.distinct
    ("`verilator_config" +: names.map(n => s"""no_inline -module "$n"""")).mkString("", "\n", "\n")
  }

  /** Options of one harness run (defaults as in docs/harness.md). `latencyMax` > `latency` draws each
    * request's latency uniformly from [latency, latencyMax], and with probability `tailProb` from
    * [latencyMax, tailLatency] instead (a long tail); `queryGap`, `reqStall` and `respGap` are
    * per-cycle probabilities of a gap in the query stream, of refusing a memory request and of
    * holding back a response beat. `simThreads` > 1 runs a multithreaded model. `fault` injects one
    * of [[Faults]] (from cycle `faultAt`): the run must then FAIL, naming it. `results` writes one line
    * `cycle port q photon` per result beat to that file. The coprocessor's harness takes the pass's
    * `frameScale`, waits by polling with `poll`, configures a bad pass with `badConfig` and reads the
    * query stream even where it is the identity with `readStream`. */
  final case class RunOptions(latency: Int = 100, bandwidth: Double = 14.0, seed: Long = 1, maxCycles: Long = 0,
                              clockGhz: Double = 1.5, wave: Option[Path] = None, waveStart: Long = 0, waveEnd: Long = Long.MaxValue,
                              latencyMax: Int = 0, queryGap: Double = 0, reqStall: Double = 0, respGap: Double = 0,
                              simThreads: Int = 1, tailProb: Double = 0, tailLatency: Int = 0, fault: Option[String] = None,
                              faultAt: Long = 0, results: Option[Path] = None, frameScale: Option[Int] = None, poll: Boolean = false,
                              badConfig: Option[String] = None, readStream: Boolean = false) {
    MapmError.check(simThreads >= 1 && simThreads <= 64, s"--sim-threads must be 1..64, got $simThreads")
    MapmError.check(latency >= 0, s"--latency must be at least 0, got $latency")
    MapmError.check(seed >= 0, s"--seed must be 0..${Long.MaxValue}, got $seed")
    MapmError.check(tailLatency >= 0, s"--tail-latency must be at least 0, got $tailLatency")
    MapmError.check(waveStart >= 0 && waveEnd >= waveStart, s"--wave-start and --wave-end must be 0 <= start <= end, got $waveStart and $waveEnd")
    MapmError.check(latencyMax == 0 || latencyMax >= latency, s"--latency-max must be at least --latency, got $latencyMax")
    MapmError.check(bandwidth > 0, s"--bandwidth must be positive, got $bandwidth")
    MapmError.check(maxCycles >= 0, s"--max-cycles must be at least 0, got $maxCycles")
    MapmError.check(clockGhz > 0, s"--clock-ghz must be positive, got $clockGhz")
    for ((n, v) <- Seq("--query-gap" -> queryGap, "--req-stall" -> reqStall, "--resp-gap" -> respGap, "--tail-prob" -> tailProb))
      MapmError.check(v >= 0 && v < 1, s"$n must be a probability in [0, 1), got $v")
    MapmError.check(tailProb == 0 || tailLatency >= (latencyMax max latency),
      s"--tail-latency must be at least --latency-max (${latencyMax max latency}) when --tail-prob is set, got $tailLatency")
    fault.foreach(f => MapmError.check(Harness.AllFaults.contains(f), s"--fault must be one of ${Harness.AllFaults.mkString(", ")}, got $f"))
    MapmError.check(faultAt >= 0, s"--fault-at must be at least 0, got $faultAt")
    def args: Seq[String] = Seq("--latency", latency.toString, "--bandwidth", bandwidth.toString, "--seed", seed.toString,
      "--max-cycles", maxCycles.toString, "--clock-ghz", clockGhz.toString) ++
      (if (latencyMax > 0) Seq("--latency-max", latencyMax.toString) else Seq.empty) ++
      Seq("--query-gap" -> queryGap, "--req-stall" -> reqStall, "--resp-gap" -> respGap, "--tail-prob" -> tailProb).filter(_._2 > 0).flatMap { case (k, v) => Seq(k, v.toString) } ++
      (if (tailProb > 0) Seq("--tail-latency", tailLatency.toString) else Seq.empty) ++
      fault.toSeq.flatMap(f => Seq("--fault", f, "--fault-at", faultAt.toString)) ++
      wave.toSeq.flatMap(w => Seq("--wave", w.toString, "--wave-start", waveStart.toString, "--wave-end", waveEnd.toString)) ++
      results.toSeq.flatMap(r => Seq("--results", r.toString)) ++
      frameScale.toSeq.flatMap(s => Seq("--frame-scale", s.toString)) ++ (if (poll) Seq("--poll") else Seq.empty) ++
      (if (readStream) Seq("--read-stream") else Seq.empty) ++
      badConfig.toSeq.flatMap(b => Seq("--bad-config", b))
  }

  /** The faults the harness injects (`--fault`, tools/harness/fault.h, docs/harness.md), on the bare
    * MAPM and the coprocessor alike. */
  val Faults: Seq[String] = Seq("node-axis", "node-child", "query-index", "unknown-id", "duplicate-response")
  /** The faults only the coprocessor's AXI4 port can take (response codes, RLAST, the write channel). */
  val AxiFaults: Seq[String] = Seq("early-last", "read-error", "write-error", "stray-b")
  /** Every fault `--fault` takes. */
  val AllFaults: Seq[String] = Faults ++ AxiFaults

  /** The verdict line, the stats (None if the harness wrote none) and the frame (raw doubles).
    * `stopped`: the run ended at `--max-cycles` as asked, every result that came out checked; not
    * a pass (the frame is unfinished), not a failure. */
  final case class Outcome(passed: Boolean, verdict: String, stats: Option[HarnessStats], frame: Option[Array[Double]],
                           stopped: Boolean = false)

  /** Runs `exe` on `image` and `expected`, writing into `outDir`; `progressLabel` shows a bar of
    * queries done from the harness's progress lines. */
  def run(exe: Path, image: Path, expected: Path, outDir: Path, opts: RunOptions, progressLabel: Option[String] = None): Outcome = {
    Files.createDirectories(outDir)
    Seq("stats.json", "frame.f64", "frame.pfm").foreach(f => Files.deleteIfExists(outDir.resolve(f)))
    val cmd = Seq(exe.toString, "--image", image.toString, "--expected", expected.toString, "--out", outDir.toString) ++ opts.args
    var bar: Option[mapm.model.Progress] = None
    var done = 0L
    val errors = new StringBuilder
    val stdout = new StringBuilder
    val progressRe = """progress (\d+) (\d+) (\d+)""".r
    val rc = Process(cmd).!(ProcessLogger(
      l => stdout.append(l).append('\n'),
      {
        case progressRe(d, total, _) =>
          if (bar.isEmpty) bar = progressLabel.map(new mapm.model.Progress(_, total.toLong))
          bar.foreach(_.advance(d.toLong - done)); done = d.toLong
        case l => errors.append(l).append('\n')
      }))
    bar.foreach(_.finish())
    val verdict = stdout.toString.linesIterator.filter(l => Seq("PASS", "FAIL", "STOPPED").exists(l.startsWith)).toSeq.lastOption.getOrElse(
      s"FAIL: harness exited with $rc without a verdict${if (errors.nonEmpty) ": " + errors.toString.trim.linesIterator.take(5).mkString(" | ") else ""}")
    val stats = Some(outDir.resolve("stats.json")).filter(Files.isRegularFile(_)).map(HarnessStats.read)
    val frame = Some(outDir.resolve("frame.f64")).filter(Files.isRegularFile(_)).map { p =>
      val b = java.nio.ByteBuffer.wrap(Files.readAllBytes(p)).order(java.nio.ByteOrder.LITTLE_ENDIAN)
      Array.fill(b.remaining / 8)(b.getDouble)
    }
    Outcome(rc == 0 && verdict.startsWith("PASS"), verdict, stats, frame, stopped = rc == 0 && verdict.startsWith("STOPPED"))
  }
}
