package mapm.cli

import mapm.evaluation._

import mapm.pipeline._

import java.nio.file.{Files, Paths}
import java.util.concurrent.Executors

import scala.concurrent.{Await, ExecutionContext, Future}
import scala.concurrent.duration.Duration

import mainargs.{Flag, ParserForMethods, arg, main}
import mapm.MapmError
import mapm.cli.Args.rtlOptionsParser
import mapm.params.{Fidelity, MapmParams}
import mapm.sim.Harness

/** `mapm evaluate`: the dissertation's chapter 4 evaluation, reproduced. Runs its four workloads
  * (Cornell box 2k over Table 4.8's 24 configurations; Cornell box 8k, Sponza corridor and Sponza
  * atrium over Table 4.11's 18) through the RTL as sweeps ([[SweepCommand]]: every run checked,
  * cost by the dissertation's method), then writes the results page ([[ResultsDoc]]; `out/results.md`,
  * or the `--results` file such as the committed `docs/results.md`): Tables
  * 4.8-4.11 and 4.13 with the dissertation's figures and ours side by side, the differences
  * explained, and the charts of Figures 4.9-4.20. `--quick` runs the 4/4/2 and 16/16/2 rows alone.
  * The SOAs are their cycle-exact timing model unless `--fidelity` says otherwise (the full RTL's
  * SOAs would take days over the 8k workloads). Runs `--jobs` at once, or as one Slurm array task
  * per workload and configuration (`--slurm`). The full run keeps each finished run in
  * `results/runs/` beside the page ([[RunArchive]]), so it can be run in parts: `--budget MIN`
  * starts no job after MIN minutes, `--resume` takes the kept runs and runs the rest; the page
  * states the parts' wall times and their sum. */
object EvaluateCommand extends Command {
  val name = "evaluate"
  val summary = "the dissertation's chapter 4 evaluation: four workloads through the RTL, a results page (out/results.md; --results docs/results.md for the committed one) with Tables 4.8-4.13"

  @main
  def evaluate(
      @arg(doc = "the 4/4/2 and 16/16/2 rows alone (minutes once the builds are cached); every run has the SOAs as timing models unless --fidelity is given") quick: Flag,
      @arg(doc = "clock of the throughput, power and GB/s figures: GHz, or 'fmax' (the slower unit's; the default)") clock: Option[String] = None,
      @arg(doc = "configurations run at once on this machine") jobs: Int = Runtime.getRuntime.availableProcessors,
      @arg(doc = "run each workload and configuration as a task of a Slurm job array and wait for the merged result (docs/cluster.md)") slurm: Flag,
      @arg(doc = "Slurm partition for --slurm (default: the cluster's)") partition: Option[String] = None,
      @arg(doc = "internal: run job N alone (a Slurm array task)") task: Option[Int] = None,
      @arg(doc = "internal: merge the jobs' results into the results page (the Slurm collect step)") collect: Flag,
      @arg(doc = "the results page to write (default: results.md in --out; the committed page is docs/results.md, written only when named here); its charts go beside it, in results/, and the full run keeps each finished run in results/runs/") results: Option[String] = None,
      @arg(doc = "take the runs an earlier full run (or part of one) kept in results/runs/ with the same code and options, and run the rest") resume: Flag,
      @arg(doc = "start no job after this many minutes; the runs left are for a later --resume (exit status 2)") budget: Option[Double] = None,
      opts: RtlOptions
  ): Int = {
    val t0 = System.nanoTime()
    Slurm.checkOptions(name, jobs, slurm.value, partition, task, collect.value)
    opts.harness() // checks the memory model's options before any work
    val fixedClock = SweepCommand.parseClock(clock)
    val resultsFile = resultsPath(results, opts.out)
    val fid = opts.fidelityOr(Fidelity.Timing)
    MapmError.check(budget.forall(_ > 0), s"evaluate: --budget must be a positive number of minutes, got ${budget.getOrElse(0.0)}")
    MapmError.check(!(quick.value && (resume.value || budget.isDefined)), "evaluate: --resume and --budget are for the full run, not --quick")
    MapmError.check(!((slurm.value || task.isDefined || collect.value) && (resume.value || budget.isDefined)),
      "evaluate: --resume and --budget are for local runs, not --slurm")
    val ws = Workloads.of(quick.value)
    def optsOf(w: Workloads.Workload) = opts.copy(scene = Harness.root.resolve(w.scene).toString, fidelity = Some(fid))
    val jobsList = ws.flatMap(w => w.configs.map(c => (w, c)))
    val log: String => Unit = l => System.err.println(s"mapm: $l")
    task match {
      case Some(i) =>
        MapmError.check(i >= 0 && i < jobsList.size, s"evaluate: --task $i is outside the ${jobsList.size} jobs")
        val (w, c) = jobsList(i)
        val work = SweepCommand.workDir(optsOf(w))
        SweepCommand.runTask(optsOf(w), c, work.resolve("tasks").resolve(i.toString), work, log)
        0
      case None if slurm.value =>
        ws.foreach(w => optsOf(w).check(w.configs)) // every scene loads and fits before anything is submitted
        // Each task reruns this evaluation with the same options (not --slurm, --partition or --jobs).
        val taskArgs = (if (quick.value) Seq("--quick") else Seq.empty) ++ clock.toSeq.flatMap(c => Seq("--clock", c)) ++
          results.toSeq.flatMap(r => Seq("--results", r)) ++ Slurm.strip(Args.toArgs(opts), Set.empty, hiddenOptions)
        val rc = Slurm.run(name, taskArgs, jobsList.size, partition, Paths.get(opts.out).resolve("evaluate-slurm"), log)
        if (rc != 0) MapmError.fail(s"evaluate: the Slurm collect step ended with exit status $rc (logs in ${Paths.get(opts.out).resolve("evaluate-slurm")})")
        println(f"evaluate: ${jobsList.size} jobs through Slurm in ${(System.nanoTime() - t0) / 1e9}%.0f s")
        0
      case None =>
        val parts = if (collect.value) Seq.empty else {
          val archive = if (quick.value) None else Some(RunArchive.beside(resultsFile))
          runLocal(ws, optsOf, jobs, resume.value, budget, archive, t0, log)
        }
        val missing = jobsList.filterNot { case (w, c) => Files.isRegularFile(SweepReport.configDir(SweepCommand.workDir(optsOf(w)), c).resolve("result.json")) }
        if (missing.nonEmpty && !collect.value) {
          System.err.println(s"mapm: evaluate: ${jobsList.size - missing.size} of ${jobsList.size} runs done, ${missing.size} left after the " +
            s"--budget; `tools/mapm evaluate --resume` (same options) runs the rest and then writes $resultsFile")
          return 2
        }
        val rows = ws.map(w => w -> w.configs.map(SweepReport.readRow(SweepCommand.workDir(optsOf(w)), _)))
        val cost = SweepCommand.unitCost(opts, fixedClock, log)
        val files = ResultsDoc.write(resultsFile, rows, cost, fid, quick.value, opts.resultsSettings, parts)
        files.foreach(f => println(s"wrote $f"))
        val failed = rows.flatMap(_._2).filterNot(_.passed)
        if (failed.nonEmpty) MapmError.fail(s"evaluate: ${failed.size} runs failed: " + failed.map(r => s"${r.label} (${r.result.failure})").mkString("; "))
        if (parts.nonEmpty) println(f"evaluate: ${jobsList.size} runs in ${parts.map(_.wallSeconds).sum}%.0f s wall" +
          (if (parts.size > 1) s" (the sum of ${parts.size} parts)" else ""))
        0
    }
  }

  /** Runs the workloads' jobs on this machine, `jobs` at a time, and returns the parts that made
    * them. Configurations are taken `jobs` at a time, each group over every workload, so the
    * builds of a group are made at once, by different threads, and each is made once.
    * With `archive` (the full run), each passed run is kept there as it ends, with the part's
    * wall time so far; `resume` first takes the runs already kept under the same key
    * ([[RunArchive]]); without it the archive starts afresh. With `budget` (minutes) no job
    * starts after that time; the jobs left are for a later `--resume`. */
  private def runLocal(ws: Seq[Workloads.Workload], optsOf: Workloads.Workload => RtlOptions, jobs: Int, resume: Boolean, budget: Option[Double],
                       archive: Option[RunArchive], t0: Long, log: String => Unit): Seq[RunArchive.Part] = {
    val code = RunArchive.codeHash
    def key(w: Workloads.Workload, c: (Int, Int, Int)) = RunArchive.key(code, w.scene, optsOf(w).archiveText(w.scene), c)
    def runDir(w: Workloads.Workload, c: (Int, Int, Int)) = SweepReport.configDir(SweepCommand.workDir(optsOf(w)), c)
    for (w <- ws; c <- w.configs) { // a result of an earlier, unrelated run in the work folder is not this run's
      Files.deleteIfExists(runDir(w, c).resolve("result.json"))
      Files.deleteIfExists(runDir(w, c).resolve("stats.json"))
    }
    archive.filterNot(_ => resume).foreach(_.clear())
    val earlier = archive.filter(_ => resume).map(_.parts).getOrElse(Seq.empty)
    val kept = archive.filter(_ => resume).toSeq.flatMap(a => for (w <- ws; c <- w.configs if a.restore(w.key, c, key(w, c), runDir(w, c))) yield (w, c))
    val todo = ws.flatMap(w => w.configs.map(c => (w, c))).filterNot(kept.contains)
    archive.foreach(a => println(s"evaluate: ${kept.size} runs kept from ${earlier.size} earlier parts in ${a.dir}, ${todo.size} to run"))
    if (todo.isEmpty) return earlier
    val part = RunArchive.Part(earlier.map(_.index).maxOption.getOrElse(0) + 1, java.time.Instant.now.toString.take(16) + "Z", 0, jobs,
      Runtime.getRuntime.availableProcessors, 0)
    val setups = todo.map(_._1).distinct.map { w =>
      val cs = todo.filter(_._1 == w).map(_._2)
      println(s"== ${w.title}: ${w.scene}, ${cs.size} configurations")
      val RtlRun.Setup(params, prep) = optsOf(w).setup(cs)
      w -> (prep, cs.zip(params).toMap)
    }.toMap
    val order = todo.map(_._2).distinct.grouped(jobs).toSeq.flatMap(g => todo.filter(j => g.contains(j._2)).sortBy(j => (ws.indexOf(j._1), g.indexOf(j._2))))
    val buildLocks = order.map(_._2).distinct.map(_ -> new Object).toMap
    val deadline = budget.map(m => t0 + (m * 60e9).toLong)
    @volatile var current = part
    def finished(w: Workloads.Workload, c: (Int, Int, Int)): Unit = synchronized {
      current = current.copy(wallSeconds = (System.nanoTime() - t0) / 1e9, runs = current.runs + 1)
      for (a <- archive) {
        if (SweepReport.readRow(SweepCommand.workDir(optsOf(w)), c).passed) a.save(w.key, c, key(w, c), part.index, runDir(w, c))
        a.savePart(current)
      }
    }
    val pool = Executors.newFixedThreadPool(math.min(jobs, order.size))
    implicit val ec: ExecutionContext = ExecutionContext.fromExecutorService(pool)
    try {
      val runs = order.map { case (w, c) =>
        Future {
          if (!deadline.exists(System.nanoTime() > _)) {
            val (prep, params) = setups(w)
            val p = params(c)
            val tag = (l: String) => log(s"[${w.key} ${p.counts.label}] $l")
            val built = buildLocks(c).synchronized(RtlRun.build(p, trace = false, optsOf(w).simThreads, tag)) // a cache hit but for the first
            SweepCommand.runOne(prep.copy(builds = Map(p -> Future.successful(built))), p, c, optsOf(w), SweepCommand.workDir(optsOf(w)), tag,
              progress = false, prefix = s"${w.key} ")
            finished(w, c)
          }
        }
      }
      runs.foreach(Await.result(_, Duration.Inf))
    } finally pool.shutdown()
    earlier :+ current.copy(wallSeconds = (System.nanoTime() - t0) / 1e9)
  }

  /** The page to write: `--results` when given, else `results.md` in the output folder, so that a
    * trial run (`--quick` above all) never replaces the committed docs/results.md unasked. */
  def resultsPath(results: Option[String], out: String): java.nio.file.Path =
    results.map(Paths.get(_)).getOrElse(Paths.get(out).resolve("results.md"))

  lazy val parser: ParserForMethods[_] = ParserForMethods(this)

  def run(args: Seq[String]): Int = Args.run(this, args, files = Set("--results"))

  override def optionDefaults: Map[String, String] = Map("--fidelity" -> Fidelity.Timing.name)
  override def hiddenOptions: Set[String] = Set("--scene")
}
