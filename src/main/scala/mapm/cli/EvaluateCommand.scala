package mapm.cli

import java.nio.file.Paths

import mainargs.{Flag, ParserForMethods, arg, main}
import mapm.MapmError
import mapm.cli.Args.rtlOptionsParser
import mapm.params.{Fidelity, MapmParams}
import mapm.sim.Harness

/** `mapm evaluate`: the dissertation's chapter 4 evaluation, reproduced. Runs its four workloads
  * (Cornell box 2k over Table 4.8's 24 configurations; Cornell box 8k, Sponza corridor and Sponza
  * atrium over Table 4.11's 18) through the RTL as sweeps ([[SweepCommand]]: every run checked,
  * cost by the dissertation's method), then writes `docs/results.md` ([[ResultsDoc]]): Tables
  * 4.8-4.11 and 4.13 with the dissertation's figures and ours side by side, the differences
  * explained, and the charts of Figures 4.9-4.20. `--quick` runs the 4/4/2 and 16/16/2 rows alone,
  * with the SOAs as their cycle-exact timing model unless `--fidelity` says otherwise. Runs
  * `--jobs` at once, or as one Slurm array task per workload and configuration (`--slurm`). */
object EvaluateCommand extends Command {
  val name = "evaluate"
  val summary = "the dissertation's chapter 4 evaluation: four workloads through the RTL, docs/results.md with Tables 4.8-4.13"

  /** A workload: its key, title, scene file (relative to the checkout) and configurations. */
  final case class Workload(key: String, title: String, scene: String, configs: Seq[(Int, Int, Int)])

  val quickConfigs: Seq[(Int, Int, Int)] = Seq((4, 4, 2), (16, 16, 2))

  def workloads(quick: Boolean): Seq[Workload] = {
    def pick(cs: Seq[(Int, Int, Int)]) = if (quick) cs.filter(quickConfigs.contains) else cs
    Seq(Workload("cornell-2k", "Cornell box, 2k photons", "test-scenes/cornell-box/scene.json", pick(MapmParams.table48Configs)),
      Workload("cornell-8k", "Cornell box, 8k photons", "test-scenes/cornell-box/scene-8k.json", pick(Dissertation.table411Configs)),
      Workload("sponza-corridor", "Sponza corridor, 8k photons", "test-scenes/sponza/corridor.json", pick(Dissertation.table411Configs)),
      Workload("sponza-atrium", "Sponza atrium, 8k photons", "test-scenes/sponza/atrium.json", pick(Dissertation.table411Configs)))
  }

  @volatile private var rawArgs: Seq[String] = Seq.empty

  @main
  def evaluate(
      @arg(doc = "the 4/4/2 and 16/16/2 rows alone, SOAs as timing models unless --fidelity is given (minutes once the builds are cached)") quick: Flag,
      @arg(doc = "clock of the throughput, power and GB/s figures: GHz, or 'fmax' (the slower unit's; the default)") clock: Option[String] = None,
      @arg(doc = "configurations run at once on this machine (default: the cores)") jobs: Int = Runtime.getRuntime.availableProcessors,
      @arg(doc = "run each workload and configuration as a task of a Slurm job array and wait for the merged result (docs/cluster.md)") slurm: Flag,
      @arg(doc = "Slurm partition for --slurm (default: the cluster's)") partition: Option[String] = None,
      @arg(doc = "internal: run job N alone (a Slurm array task)") task: Option[Int] = None,
      @arg(doc = "internal: merge the jobs' results into the results page (the Slurm collect step)") collect: Flag,
      @arg(doc = "the results page to write (its charts go beside it, in results/)") results: String = "docs/results.md",
      opts: RtlOptions
  ): Int = {
    val t0 = System.nanoTime()
    MapmError.check(opts.scene == RenderCommand.defaultScene, "evaluate: it runs its four workloads; --scene does not apply")
    Slurm.checkOptions(name, jobs, slurm.value, partition, task, collect.value)
    opts.harness() // checks the memory model's options before any work
    val fixedClock = SweepCommand.parseClock(clock)
    val resultsFile = Paths.get(results)
    val fid = if (quick.value && !rawArgs.exists(_.startsWith("--fidelity"))) Fidelity.Timing else opts.fidelity
    val ws = workloads(quick.value)
    def optsOf(w: Workload) = opts.copy(scene = Harness.root.resolve(w.scene).toString, fidelity = fid)
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
        val taskArgs = Slurm.strip(rawArgs, Set("--slurm"), Set("--partition", "--jobs"))
        val rc = Slurm.run(name, taskArgs, jobsList.size, partition, Paths.get(opts.out).resolve("evaluate-slurm"), log)
        if (rc != 0) MapmError.fail(s"evaluate: the Slurm collect step ended with exit status $rc (logs in ${Paths.get(opts.out).resolve("evaluate-slurm")})")
        println(f"evaluate: ${jobsList.size} jobs through Slurm in ${(System.nanoTime() - t0) / 1e9}%.0f s")
        0
      case None =>
        if (!collect.value) for (w <- ws) {
          println(s"== ${w.title}: ${w.scene}, ${w.configs.size} configurations")
          SweepCommand.runLocal(optsOf(w), w.configs, jobs, SweepCommand.workDir(optsOf(w)), log)
        }
        val rows = ws.map(w => w -> w.configs.map(SweepReport.readRow(SweepCommand.workDir(optsOf(w)), _)))
        val cost = SweepCommand.unitCost(opts, fixedClock, log)
        val wall = if (collect.value) None else Some((System.nanoTime() - t0) / 1e9)
        val files = ResultsDoc.write(resultsFile, rows, cost, fid, quick.value, opts, wall, jobs)
        files.foreach(f => println(s"wrote $f"))
        val failed = rows.flatMap(_._2).filterNot(_.passed)
        if (failed.nonEmpty) MapmError.fail(s"evaluate: ${failed.size} runs failed: " + failed.map(r => s"${r.label} (${r.result.failure})").mkString("; "))
        wall.foreach(s => println(f"evaluate: ${jobsList.size} runs in $s%.0f s wall"))
        0
    }
  }

  def run(args: Seq[String]): Int = { rawArgs = args; Args.run(ParserForMethods(this), args, name, files = Set("--results")) }
}
