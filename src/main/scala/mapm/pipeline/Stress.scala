package mapm.pipeline

import java.nio.file.{Files, Path}

import mapm.MapmError
import mapm.numerics.FloatFormat
import mapm.sim.Harness

/** The stress campaign of `mapm stress`: the whole MAPM's RTL under many random memory systems.
  * For each configuration ([[Stress.Entry]]) and each seed, the harness runs a small frame with
  * the memory behaviour the seed draws ([[Stress.draw]]), and every run is checked as `render`
  * checks it, its SO counters against the model's too. Stops at the first failing run and
  * prints the `render` command that replays it ([[Stress.renderCommand]]). */
object Stress {
  /** One configuration entry: counts and an optional format (else the scene's, else fp32). */
  final case class Entry(tsm: Int, som: Int, soa: Int, format: Option[FloatFormat]) {
    def label: String = s"$tsm/$som/$soa${format.map(f => s":${f.name}").getOrElse("")}"
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

  /** The `render` command line that replays run `o` of configuration `e` on `scene` (with the
    * sizes `tuning`), with a waveform of cycles [waveStart, waveEnd]. */
  def renderCommand(scene: String, e: Entry, g: Int, o: Harness.RunOptions, waveStart: Long, waveEnd: Long, tuning: Tuning = Tuning()): String =
    (Seq("tools/mapm", "render", "--scene", scene, "--tsm", e.tsm.toString, "--som", e.som.toString, "--soa", e.soa.toString, "--g", g.toString) ++
      e.format.toSeq.flatMap(f => Seq("--format", f.name)) ++ tuning.sopL2Banks.toSeq.flatMap(b => Seq("--sop-l2-banks", b.toString)) ++
      tuning.soBus.toSeq.flatMap(b => Seq("--so-bus", b.name)) ++
      (if (tuning.coproc) Seq.empty else Seq("--bare")) ++ // render's default is the coprocessor
      Seq("--query-order", "host") ++ // the campaign's images stream the queries in the host's order
      o.args.grouped(2).filterNot(kv => kv.head == "--max-cycles" || kv.head == "--clock-ghz").flatten ++
      Seq("--max-cycles", o.maxCycles.toString, "--wave", "stress-fail.fst", "--wave-start", waveStart.toString, "--wave-end", waveEnd.toString))
      .mkString(" ")

  /** Runs `seeds` seeds from `firstSeed` of each entry on `scene` with `g` guard digits, failing a
    * run not finished after `maxCycles`; writes `stress.csv` (a row per run) into `outDir` and
    * prints a line per entry and the total. The model side runs once per format, with `threads`
    * worker threads; every configuration takes the SOP L2 structure and the Data bus of `tuning`. Fails
    * ([[MapmError]]) at the first failing run. */
  def run(scene: String, entries: Seq[Entry], g: Int, seeds: Int, firstSeed: Long, maxCycles: Long, outDir: Path, threads: Int,
          tuning: Tuning = Tuning()): Unit = {
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
        RtlRun.prepare(scene, e.format, g, outDir.resolve(s"stress-${e.format.map(_.name).getOrElse("scene-format")}").toString, threads, coproc = tuning.coproc))
      val p = Configure.of(e.tsm, e.som, e.soa, prep.frame.format, g, tuning = tuning)
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
          println(s"reproduce: ${renderCommand(scene, e, g, o, (at - 2000) max 0, at + 10, tuning)}")
          fail(s"stress: ${e.label} seed $seed failed after $total passing runs: $why")
        }
        total += 1
        sos += prep.model.count
        cycles += s.get.cycles
      }
      bar.finish()
      val cs = cycles.result().sorted
      println(f"${e.label}%-14s ${p.numbers.format.name}%-6s $seeds%d seeds PASS: ${prep.model.count}%d SOs each, none lost or duplicated" +
        (if (p.sim.coproc) ", the frame buffer bit-equal to the model's" else "") + s"; cycles min ${cs.head}, median ${cs(cs.size / 2)}, max ${cs.last}")
    }
    Files.write(csv, rows.result().mkString("", "\n", "\n").getBytes("UTF-8"))
    println(f"stress: $total%d runs passed ($sos%d shader operations checked, 0 lost, 0 duplicated) in ${(System.nanoTime() - wall0) / 1e9}%.0f s")
    println(s"wrote $csv")
  }
}
