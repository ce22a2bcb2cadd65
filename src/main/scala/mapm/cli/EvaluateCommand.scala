package mapm.cli

import mapm.evaluation.{Evaluation, ResultsDoc, RunArchive, Slurm, Workloads}

import java.nio.file.Paths

import mainargs.{Flag, ParserForMethods, arg, main}
import mapm.MapmError
import mapm.cli.Args.rtlOptionsParser
import mapm.params.Fidelity

/** `mapm evaluate`: the dissertation's chapter 4 evaluation, reproduced. Runs its four workloads
  * (Cornell box 2k over Table 4.8's 24 configurations; Cornell box 8k, Sponza corridor and Sponza
  * atrium over Table 4.11's 18) through the RTL ([[Evaluation]], as sweeps: every run checked,
  * cost by the dissertation's method), then writes the results page ([[mapm.evaluation.ResultsDoc]]; `out/results.md`,
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
      @arg(doc = "LABEL=PAGE: another full run's results page (e.g. table4.2=docs/results-table4.2/results.md, the dissertation's hierarchy): the cycles of the runs kept beside it stand beside ours in Tables 4.8 and 4.11, under LABEL") beside: Option[String] = None,
      opts: RtlOptions
  ): Int = {
    val t0 = System.nanoTime()
    Slurm.checkOptions(name, jobs, slurm.value, partition, task, collect.value)
    opts.harness() // checks the memory model's options before any work
    val fixedClock = SweepCommand.parseClock(clock)
    val resultsFile = resultsPath(results, opts.out)
    MapmError.check(budget.forall(_ > 0), s"evaluate: --budget must be a positive number of minutes, got ${budget.getOrElse(0.0)}")
    MapmError.check(!(quick.value && (resume.value || budget.isDefined)), "evaluate: --resume and --budget are for the full run, not --quick")
    MapmError.check(!((slurm.value || task.isDefined || collect.value) && (resume.value || budget.isDefined)),
      "evaluate: --resume and --budget are for local runs, not --slurm")
    val eval = Evaluation(Workloads.of(quick.value), opts.settings(Fidelity.Timing))
    val besideRun = beside.map(ResultsDoc.Beside.load(_, eval.workloads)) // a wrong page fails before any run
    val log: String => Unit = l => System.err.println(s"mapm: $l")
    task match {
      case Some(i) =>
        eval.runTask(i, log)
        0
      case None if slurm.value =>
        eval.check() // every scene loads and fits before anything is submitted
        // Each task reruns this evaluation with the same options (not --slurm, --partition or --jobs).
        val taskArgs = (if (quick.value) Seq("--quick") else Seq.empty) ++ clock.toSeq.flatMap(c => Seq("--clock", c)) ++
          results.toSeq.flatMap(r => Seq("--results", r)) ++ beside.toSeq.flatMap(b => Seq("--beside", b)) ++ Slurm.strip(Args.toArgs(opts), Set.empty, hiddenOptions)
        val logs = Paths.get(opts.out).resolve("evaluate-slurm")
        val rc = Slurm.run(name, taskArgs, eval.jobs.size, partition, logs, log)
        if (rc != 0) MapmError.fail(s"evaluate: the Slurm collect step ended with exit status $rc (logs in $logs)")
        println(f"evaluate: ${eval.jobs.size} jobs through Slurm in ${(System.nanoTime() - t0) / 1e9}%.0f s")
        0
      case None =>
        val parts = if (collect.value) Seq.empty else {
          val archive = if (quick.value) None else Some(RunArchive.beside(resultsFile))
          eval.runLocal(jobs, resume.value, budget, archive, t0, log)
        }
        val missing = eval.missing
        if (missing.nonEmpty && !collect.value) {
          System.err.println(s"mapm: evaluate: ${eval.jobs.size - missing.size} of ${eval.jobs.size} runs done, ${missing.size} left after the " +
            s"--budget; `tools/mapm evaluate --resume` (same options) runs the rest and then writes $resultsFile")
          return 2
        }
        eval.report(resultsFile, fixedClock, quick.value, parts, log, besideRun)
        if (parts.nonEmpty) println(f"evaluate: ${eval.jobs.size} runs in ${parts.map(_.wallSeconds).sum}%.0f s wall" +
          (if (parts.size > 1) s" (the sum of ${parts.size} parts)" else ""))
        0
    }
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
