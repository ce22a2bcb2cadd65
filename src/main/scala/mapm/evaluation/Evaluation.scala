package mapm.evaluation

import java.nio.file.{Files, Path}

import scala.concurrent.Future

import mapm.MapmError
import mapm.pipeline.{RtlRun, RunSettings}
import mapm.sim.Harness

/** The dissertation's chapter 4 evaluation (`mapm evaluate`): its workloads ([[Workloads]]), each
  * run as a [[Sweep]] with the settings `base` on the workload's scene, and the results page
  * ([[ResultsDoc]]) made from the runs' result files.
  *
  * @param workloads the workloads, each over its configurations
  * @param base      the settings every run shares; the scene is each workload's
  */
final case class Evaluation(workloads: Seq[Workloads.Workload], base: RunSettings) {
  /** The settings of workload `w`'s runs. */
  def settings(w: Workloads.Workload): RunSettings = base.copy(scene = Harness.root.resolve(w.scene).toString)

  /** Every run: a workload and a configuration, in the order of the Slurm array's tasks. */
  val jobs: Seq[(Workloads.Workload, (Int, Int, Int))] = workloads.flatMap(w => w.configs.map(c => (w, c)))

  /** The folder of one run's result and statistics files. */
  def runDir(w: Workloads.Workload, c: (Int, Int, Int)): Path = SweepReport.configDir(settings(w).workDir, c)

  /** The runs that have no result file. */
  def missing: Seq[(Workloads.Workload, (Int, Int, Int))] = jobs.filterNot { case (w, c) => Files.isRegularFile(runDir(w, c).resolve("result.json")) }

  /** Fails, before anything is submitted, when a workload's scene does not load or fit its configurations. */
  def check(): Unit = workloads.foreach(w => settings(w).check(w.configs))

  /** A Slurm array task: run `i` of [[jobs]] alone. */
  def runTask(i: Int, log: String => Unit): Unit = {
    MapmError.check(i >= 0 && i < jobs.size, s"evaluate: --task $i is outside the ${jobs.size} jobs")
    val (w, c) = jobs(i)
    Sweep.runTask(settings(w), c, Sweep.taskDir(settings(w), i), log)
  }

  /** Runs the jobs on this machine, `threads` at a time, and returns the parts that made them.
    * Configurations are taken `threads` at a time, each group over every workload, so the builds
    * of a group are made at once, by different threads, and each is made once. With `archive`
    * (the full run), each passed run is kept there as it ends, with the part's wall time so far;
    * `resume` first takes the runs already kept under the same key ([[RunArchive]]); without it
    * the archive starts afresh. With `budget` (minutes after `t0`) no job starts after that time;
    * the jobs left are for a later `--resume`. */
  def runLocal(threads: Int, resume: Boolean, budget: Option[Double], archive: Option[RunArchive], t0: Long,
               log: String => Unit): Seq[RunArchive.Part] = {
    val code = RunArchive.codeHash
    def key(w: Workloads.Workload, c: (Int, Int, Int)) = RunArchive.key(code, w.scene, settings(w).archiveText(w.scene), c)
    for ((w, c) <- jobs) { // a result of an earlier, unrelated run in the work folder is not this run's
      Files.deleteIfExists(runDir(w, c).resolve("result.json"))
      Files.deleteIfExists(runDir(w, c).resolve("stats.json"))
    }
    archive.filterNot(_ => resume).foreach(_.clear())
    val earlier = archive.filter(_ => resume).map(_.parts).getOrElse(Seq.empty)
    val kept = archive.filter(_ => resume).toSeq.flatMap(a => jobs.filter { case (w, c) => a.restore(w.key, c, key(w, c), runDir(w, c)) })
    val todo = jobs.filterNot(kept.contains)
    archive.foreach(a => println(s"evaluate: ${kept.size} runs kept from ${earlier.size} earlier parts in ${a.dir}, ${todo.size} to run"))
    if (todo.isEmpty) return earlier
    val part = RunArchive.Part(earlier.map(_.index).maxOption.getOrElse(0) + 1, java.time.Instant.now.toString.take(16) + "Z", 0, threads,
      Runtime.getRuntime.availableProcessors, 0)
    val setups = todo.map(_._1).distinct.map { w =>
      val cs = todo.filter(_._1 == w).map(_._2)
      println(s"== ${w.title}: ${w.scene}, ${cs.size} configurations")
      val RtlRun.Setup(params, prep) = settings(w).setup(cs)
      w -> (prep, cs.zip(params).toMap)
    }.toMap
    val order = todo.map(_._2).distinct.grouped(threads).toSeq
      .flatMap(g => todo.filter(j => g.contains(j._2)).sortBy(j => (workloads.indexOf(j._1), g.indexOf(j._2))))
    val buildLocks = order.map(_._2).distinct.map(_ -> new Object).toMap
    @volatile var current = part
    def finished(w: Workloads.Workload, c: (Int, Int, Int)): Unit = synchronized {
      current = current.copy(wallSeconds = (System.nanoTime() - t0) / 1e9, runs = current.runs + 1)
      for (a <- archive) {
        if (SweepReport.readRow(settings(w).workDir, c).passed) a.save(w.key, c, key(w, c), part.index, runDir(w, c))
        a.savePart(current)
      }
    }
    JobRunner.run(order, threads, budget.map(m => t0 + (m * 60e9).toLong)) { case (w, c) =>
      val (prep, params) = setups(w)
      val p = params(c)
      val tag = (l: String) => log(s"[${w.key} ${p.counts.label}] $l")
      val built = buildLocks(c).synchronized(RtlRun.build(p, trace = false, base.harness.simThreads, tag)) // a cache hit but for the first
      Sweep.runOne(prep.copy(builds = Map(p -> Future.successful(built))), p, c, settings(w), tag, progress = false, prefix = s"${w.key} ")
      finished(w, c)
    }
    earlier :+ current.copy(wallSeconds = (System.nanoTime() - t0) / 1e9)
  }

  /** Writes the results page `file` (and its charts) from the runs' result files, the cost at
    * `fixedClock` or the slower unit's fmax; `parts` are the local parts that made the runs;
    * `beside` another run shown beside them. Fails when any run failed. Returns the files written. */
  def report(file: Path, fixedClock: Option[Double], quick: Boolean, parts: Seq[RunArchive.Part], log: String => Unit,
             beside: Option[ResultsDoc.Beside] = None): Seq[Path] = {
    val rows = workloads.map(w => w -> w.configs.map(SweepReport.readRow(settings(w).workDir, _)))
    val cost = Sweep.unitCost(base, fixedClock, log)
    val files = ResultsDoc.write(file, rows, cost, quick, base, parts, beside)
    files.foreach(f => println(s"wrote $f"))
    val failed = rows.flatMap(_._2).filterNot(_.passed)
    if (failed.nonEmpty) MapmError.fail(s"evaluate: ${failed.size} runs failed: " + failed.map(r => s"${r.label} (${r.result.failure})").mkString("; "))
    files
  }
}
