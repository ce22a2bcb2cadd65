package mapm.evaluation

import java.nio.file.{Files, Path, Paths}

import mapm.MapmError
import mapm.costflow.UnitCostCache
import mapm.params.{Fidelity, MapmParams}
import mapm.pipeline.{ModelRun, RtlRun, RunSettings}

/** A design-space sweep over TSM/SOM/SOA configurations on one scene through the RTL (`mapm
  * sweep`): the model side runs once, each configuration is emitted, verilated and run with its
  * cached builds, and checked like `render`'s. Each run leaves `result.json` and `stats.json` in
  * its folder under [[RunSettings.workDir]]; the CSV and charts are made from those files alone
  * ([[SweepReport]]), so local runs, Slurm tasks and `evaluate` share them. */
object Sweep {
  /** Runs the configurations `list`, `jobs` at a time ([[JobRunner]]), on a frame prepared once;
    * each leaves its result file. */
  def runLocal(s: RunSettings, list: Seq[(Int, Int, Int)], jobs: Int, log: String => Unit): Unit = {
    val RtlRun.Setup(params, prep) = s.setup(list)
    println(s"sweep of ${params.size} configurations on ${prep.config.file}, $jobs at once, ${s.tuning.summary}: ${prep.model.count} shader operations, ${prep.model.tsOps} TS ops" +
      (if (s.fidelity == Fidelity.Timing) "; SOAs as timing models (cycle-exact; colours from the model, not checked)" else ""))
    JobRunner.run(params.zip(list), jobs) { case (p, c) =>
      runOne(prep, p, c, s, if (jobs == 1) log else (l: String) => log(s"[${p.counts.label}] $l"), progress = jobs == 1)
    }
  }

  /** One configuration `c` (made as `p`) on a prepared frame: runs it, prints its line (after
    * `prefix`), writes its result file into its folder under `s`'s work folder. */
  def runOne(prep: RtlRun.Prepared, p: MapmParams, c: (Int, Int, Int), s: RunSettings, log: String => Unit,
             progress: Boolean, prefix: String = ""): Unit = {
    val dir = SweepReport.configDir(s.workDir, c)
    val r = RtlRun.runConfig(prep, p, s.harness, dir, log, progress)
    val st = r.outcome.stats
    def orNaN(v: Option[Double]): Double = v.getOrElse(Double.NaN)
    println(f"$prefix${p.counts.label}%-8s ${if (r.passed) "PASS" else if (r.stopped) "STOPPED" else "FAIL"} cycles ${orNaN(st.map(_.cycles.toDouble))}%.0f " +
      f"SO/cycle ${orNaN(st.map(_.soPerCycle))}%.3f TS ops/cycle ${orNaN(st.flatMap(_.tsOpsPerCycle))}%.3f " +
      f"simulated ${orNaN(st.map(_.simulatedCyclesPerSecond))}%.0f cycles/s${if (r.passed) "" else ": " + r.failure}")
    SweepReport.writeResult(dir, SweepReport.TaskResult(p.counts.label, c._1, c._2, c._3, r.passed, if (r.passed) "" else r.failure,
      r.beside.map { case (k, v) => s"$k (beside the model)" -> v } ++ r.times))
  }

  /** A Slurm array task: prepares the frame in its own folder `own` (the model is deterministic; no
    * task writes another's files) and runs configuration `c` into the shared work folder. */
  def runTask(s: RunSettings, c: (Int, Int, Int), own: Path, log: String => Unit): Unit = {
    val RtlRun.Setup(Seq(p), prep) = s.copy(out = own.toString).setup(Seq(c))
    runOne(prep, p, c, s, log, progress = false)
  }

  /** The folder of a Slurm array task's own frame, task `i` of a sweep with settings `s`. */
  def taskDir(s: RunSettings, i: Int): Path = s.workDir.resolve("tasks").resolve(i.toString)

  /** Writes the CSV and charts from the configurations' result files into `s`'s output folder,
    * with the cost columns when `withCost` (at `fixedClock`, else the slower unit's fmax); fails
    * when any configuration failed. */
  def report(s: RunSettings, list: Seq[(Int, Int, Int)], fixedClock: Option[Double], withCost: Boolean, log: String => Unit): Unit = {
    val work = s.workDir
    val rows = list.map(SweepReport.readRow(work, _))
    val cost = if (!withCost) None else Some(unitCost(s, fixedClock, log))
    val clockGHz = cost.map(_.clockGHz).getOrElse(fixedClock.getOrElse(s.harness.clockGhz))
    cost.foreach(c => println(f"cost: ${c.soa.top} ${c.soa.areaUm2 / 1e6}%.4f mm^2, fmax ${c.soa.fmaxGHz}%.3f GHz; ${c.tsa.top} " +
      f"${c.tsa.areaUm2 / 1e6}%.4f mm^2, fmax ${c.tsa.fmaxGHz}%.3f GHz; clock ${c.clockGHz}%.3f GHz (${c.clockSource})"))
    val name = RtlRun.frameName(s.scene, s.arith)
    val outDir = Paths.get(s.out)
    Files.createDirectories(outDir)
    val csv = outDir.resolve(s"$name-sweep.csv")
    Files.write(csv, SweepReport.csv(rows, cost, clockGHz).getBytes("UTF-8"))
    val charts = SweepReport.charts(outDir, name, name, rows, cost, clockGHz)
    (csv +: charts).foreach(f => println(s"wrote $f"))
    val failed = rows.filterNot(_.passed)
    if (failed.nonEmpty) MapmError.fail(s"sweep: ${failed.size} of ${rows.size} configurations failed: " +
      failed.map(r => s"${r.label} (${r.result.failure})").mkString("; "))
  }

  /** The SOA's and TSA's figures at `s`'s number format, g and arithmetic, and the clock: `fixed`,
    * or the slower unit's fmax. */
  def unitCost(s: RunSettings, fixed: Option[Double], log: String => Unit): SweepReport.Cost = {
    val fmt = s.format.orElse(ModelRun.loadScene(s.scene).format).getOrElse(mapm.numerics.FloatFormat.fp32)
    val soa = UnitCostCache.get("soa", fmt, s.g, s.arith, log)
    val tsa = UnitCostCache.get("tsa", fmt, s.g, s.arith, log)
    val fmax = math.min(soa.fmaxGHz, tsa.fmaxGHz)
    SweepReport.Cost(soa, tsa, fixed.getOrElse(fmax), if (fixed.isDefined) "--clock" else s"fmax of the slower unit, the ${if (soa.fmaxGHz <= tsa.fmaxGHz) "SOA" else "TSA"}")
  }
}
