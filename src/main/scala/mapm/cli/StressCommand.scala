package mapm.cli

import mapm.pipeline._

import java.nio.file.{Files, Paths}

import mainargs.{ParserForMethods, arg, main}
import mapm.MapmError
import mapm.model.Parallel
import mapm.numerics.FloatFormat
import mapm.sim.Harness

/** `mapm stress`: the whole MAPM's RTL under many random memory systems. For each configuration
  * (TSM/SOM/SOA, optionally `:format`) and each seed, the harness runs a small frame with the
  * memory behaviour the seed draws ([[StressCommand.draw]]): base and random latency, a long
  * latency tail, response reordering (the harness's DRAM, seeded), refused requests, response gaps,
  * query-stream gaps and bandwidth. Every run is checked as `render` checks it: every shader
  * operation bit-exact against the model (none lost, none duplicated, none unexpected), the frame
  * bit-equal, the TS-op and SO counters equal to the model's.
  *
  * Each configuration is verilated once. Stops at the first failing run and prints the `render`
  * command that reproduces it, with a waveform window ending at the failure. Exit 0 only when every
  * run passed. Writes `stress.csv` (one row per run) into `--out`. */
object StressCommand extends Command {
  val name = "stress"
  val summary = "run the RTL over many seeds of random memory latency, reordering and stalls; check every run"
  val defaultScene = "test-scenes/cornell-box/scene-small.json"
  val defaultConfigs = "1/1/1,2/1/2,4/4/2,3/2/3,2/2/2:fp16"

  /** One configuration entry: counts and an optional format (else the scene's, else fp32). */
  final case class Entry(tsm: Int, som: Int, soa: Int, format: Option[FloatFormat]) {
    def label: String = s"$tsm/$som/$soa${format.map(f => s":${f.name}").getOrElse("")}"
  }

  /** "1/1/1,2/2/2:fp16" into entries; a [[MapmError]] naming a bad one. */
  def parseEntries(s: String): Seq[Entry] =
    s.split(',').map(_.trim).filter(_.nonEmpty).toSeq.map { e =>
      val (counts, fmt) = e.split(':') match {
        case Array(c) => (c, None)
        case Array(c, f) => (c, Some(FloatFormat.parse(f)))
        case _ => MapmError.fail(s"stress: --configs entry '$e' is not TSM/SOM/SOA or TSM/SOM/SOA:FORMAT")
      }
      val (t, m, a) = SweepCommand.parseConfigs(counts).headOption.getOrElse(MapmError.fail(s"stress: empty --configs entry '$e'"))
      Entry(t, m, a, fmt)
    }

  /** The memory system of seed `seed`: every random choice of a run, drawn from the seed alone, so
    * `render` with the same options (and `--seed`) replays the run cycle for cycle. */
  def draw(seed: Long, maxCycles: Long): Harness.RunOptions = {
    val r = new scala.util.Random(seed * 0x2545f4914f6cdd1dL + 17)
    val latency = r.nextInt(41)
    val latencyMax = latency + Seq(0, 10, 60, 300)(r.nextInt(4))
    val tail = r.nextInt(3) == 0
    def p(max: Double) = math.round(r.nextDouble() * max * 100) / 100.0 // two decimals: short on the command line
    Harness.RunOptions(latency = latency, latencyMax = if (latencyMax > latency) latencyMax else 0,
      bandwidth = Seq(4.0, 8.0, 14.0, 32.0)(r.nextInt(4)), seed = seed, maxCycles = maxCycles,
      queryGap = p(0.6), reqStall = p(0.5), respGap = p(0.5),
      tailProb = if (tail) Seq(0.01, 0.05)(r.nextInt(2)) else 0, tailLatency = if (tail) latencyMax + 200 + r.nextInt(2801) else 0)
  }

  /** The `render` command line that replays run `o` of configuration `e` on `scene`, with a
    * waveform of cycles [waveStart, waveEnd]. */
  def renderCommand(scene: String, e: Entry, g: Int, o: Harness.RunOptions, waveStart: Long, waveEnd: Long): String =
    (Seq("tools/mapm", "render", "--scene", scene, "--tsm", e.tsm.toString, "--som", e.som.toString, "--soa", e.soa.toString, "--g", g.toString) ++
      e.format.toSeq.flatMap(f => Seq("--format", f.name)) ++
      o.args.grouped(2).filterNot(kv => kv.head == "--max-cycles" || kv.head == "--clock-ghz").flatten ++
      Seq("--max-cycles", o.maxCycles.toString, "--wave", "stress-fail.fst", "--wave-start", waveStart.toString, "--wave-end", waveEnd.toString))
      .mkString(" ")

  @main
  def stress(
      @arg(doc = "seeds per configuration") seeds: Int = 100,
      @arg(doc = "first seed (seeds run first-seed, first-seed+1, ...)") firstSeed: Long = 1,
      @arg(doc = "configurations TSM/SOM/SOA or TSM/SOM/SOA:FORMAT, comma separated") configs: String = defaultConfigs,
      @arg(doc = "scene description file (JSON); small: every seed is a whole frame") scene: String = defaultScene,
      @arg(name = "g", doc = "guard digits of the SOA's online units") g: Int = 3,
      @arg(doc = "fail a run that has not finished after this many cycles") maxCycles: Long = 5000000,
      @arg(doc = "output folder") out: String = "out",
      @arg(doc = "worker threads of the model") threads: Int = Parallel.defaultThreads
  ): Int = {
    MapmError.check(seeds >= 1 && seeds <= 1000000, s"stress: --seeds must be 1..1000000, got $seeds")
    MapmError.check(firstSeed >= 0, s"stress: --first-seed must be at least 0, got $firstSeed")
    MapmError.check(maxCycles >= 1000, s"stress: --max-cycles must be at least 1000, got $maxCycles")
    val entries = parseEntries(configs)
    MapmError.check(entries.nonEmpty, "stress: no configurations given")
    val outDir = Paths.get(out)
    Files.createDirectories(outDir)
    val csv = outDir.resolve("stress.csv")
    val rows = Seq.newBuilder[String]
    rows += "config,format,seed,latency,latency_max,tail_prob,tail_latency,bandwidth,query_gap,req_stall,resp_gap,cycles,so_checked,result"
    val wall0 = System.nanoTime()
    var total = 0L
    var sos = 0L
    // Frames by format: the model side runs once per format, each in its own folder.
    val preps = scala.collection.mutable.Map.empty[Option[FloatFormat], RtlRun.Prepared]
    def fail(msg: String): Nothing = {
      Files.write(csv, rows.result().mkString("", "\n", "\n").getBytes("UTF-8"))
      MapmError.fail(msg)
    }
    for (e <- entries) {
      val prep = preps.getOrElseUpdate(e.format,
        RtlRun.prepare(scene, e.format, g, outDir.resolve(s"stress-${e.format.map(_.name).getOrElse("scene-format")}").toString, threads))
      val p = mapm.pipeline.Configure.of(e.tsm, e.som, e.soa, prep.frame.format, g)
      val cycles = Seq.newBuilder[Long]
      val bar = new mapm.model.Progress(s"stress ${e.label}", seeds.toLong)
      for (seed <- firstSeed until firstSeed + seeds) {
        val o = draw(seed, maxCycles)
        val run = RtlRun.runConfig(prep, p, o, prep.work.resolve(s"stress-${p.name}"), l => System.err.println(s"mapm: $l"))
        bar.advance(1)
        val s = run.outcome.stats
        val countersOk = s.exists(st => st.counters.get("soIssued").contains(prep.model.count) && st.soIssued == prep.model.count &&
          st.soPassingCond == prep.model.passing)
        val ok = run.passed && countersOk
        rows += (Seq(e.label, p.numbers.format.name, seed.toString, o.latency.toString, (o.latencyMax max o.latency).toString,
          o.tailProb.toString, o.tailLatency.toString, o.bandwidth.toString, o.queryGap.toString, o.reqStall.toString, o.respGap.toString,
          s.map(_.cycles.toString).getOrElse(""), s.map(_.soIssued.toString).getOrElse(""), if (ok) "PASS" else "FAIL").mkString(","))
        if (!ok) {
          bar.finish()
          val at = s.map(_.cycles).getOrElse(maxCycles)
          val why = if (run.stopped) s"not finished within --max-cycles $maxCycles (${s.fold("?")(st => s"${st.queriesCompleted} of ${st.queries} queries complete")})"
            else if (!run.passed) run.failure else "the SO counters differ from the model's"
          println(s"FAIL ${e.label} seed $seed: $why")
          println(s"reproduce: ${renderCommand(scene, e, g, o, (at - 2000) max 0, at + 10)}")
          fail(s"stress: ${e.label} seed $seed failed after $total passing runs: $why")
        }
        total += 1
        sos += prep.model.count
        cycles += s.get.cycles
      }
      bar.finish()
      val cs = cycles.result().sorted
      println(f"${e.label}%-14s ${p.numbers.format.name}%-6s $seeds%d seeds PASS: ${prep.model.count}%d SOs each, none lost or duplicated; " +
        s"cycles min ${cs.head}, median ${cs(cs.size / 2)}, max ${cs.last}")
    }
    Files.write(csv, rows.result().mkString("", "\n", "\n").getBytes("UTF-8"))
    println(f"stress: $total%d runs passed ($sos%d shader operations checked, 0 lost, 0 duplicated) in ${(System.nanoTime() - wall0) / 1e9}%.0f s")
    println(s"wrote $csv")
    0
  }

  lazy val parser: ParserForMethods[_] = ParserForMethods(this)

  def run(args: Seq[String]): Int = Args.run(this, args)
}
