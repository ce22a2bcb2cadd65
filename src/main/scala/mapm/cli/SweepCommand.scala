package mapm.cli

import mapm.evaluation._

import mapm.costflow._
import mapm.pipeline._

import java.nio.file.{Files, Path, Paths}
import java.util.concurrent.Executors

import scala.concurrent.{Await, ExecutionContext, Future}
import scala.concurrent.duration.Duration

import mainargs.{Flag, ParserForMethods, arg, main}
import mapm.MapmError
import mapm.cli.Args.rtlOptionsParser
import mapm.numerics.Arith
import mapm.params.MapmParams

/** `mapm sweep`: a design-space sweep over TSM/SOM/SOA configurations (default: the 24 of Table
  * 4.8) on one scene through the RTL ([[RtlRun]]: the model side runs once, each configuration is
  * emitted, verilated and run with its cached builds). Every run is checked like `render`'s.
  *
  * Runs `--jobs` configurations at once, or each as a task of a Slurm job array (`--slurm`,
  * [[Slurm]]). Each run leaves `result.json` and `stats.json` in its folder; the CSV and charts
  * are made from those files alone ([[SweepReport]]): `<scene>-sweep.csv` (cycles, SO/cycle, TS
  * ops/cycle, speed-up, billion SO/s at the clock, area and power by the dissertation's method,
  * throughput per area and per power, bytes, GB/s, hit rates, simulation speed, verdict) and the
  * charts of Figures 4.9-4.20 grouped by TSM count. */
object SweepCommand extends Command {
  val name = "sweep"
  val summary = "design-space sweep over TSM/SOM/SOA configurations through the RTL: CSV with cost, charts; local jobs or Slurm"

  /** "1/1/2,2/1/2" into triples; a [[MapmError]] naming a bad entry. */
  def parseConfigs(s: String): Seq[(Int, Int, Int)] =
    s.split(',').map(_.trim).filter(_.nonEmpty).toSeq.map { c =>
      c.split('/').map(_.trim.toIntOption) match {
        case Array(Some(t), Some(m), Some(a)) => (t, m, a)
        case _ => MapmError.fail(s"sweep: --configs entry '$c' is not TSM/SOM/SOA (e.g. 16/16/2)")
      }
    }

  /** `--clock`: None (fmax with cost, else the harness's --clock-ghz), `fmax`, or GHz. */
  def parseClock(s: Option[String]): Option[Double] = s.filterNot(_ == "fmax").map { v =>
    val ghz = v.toDoubleOption.getOrElse(MapmError.fail(s"sweep: --clock takes GHz or 'fmax', got '$v'"))
    MapmError.check(ghz > 0 && ghz <= 20, s"sweep: --clock must be in (0, 20] GHz, got $ghz")
    ghz
  }

  @main
  def sweep(
      @arg(doc = "configurations TSM/SOM/SOA, comma separated (default: the 24 of Table 4.8)") configs: Option[String] = None,
      @arg(doc = "clock of the throughput, power and GB/s figures: GHz, or 'fmax' (the slower unit's, from the cost flow; the default)") clock: Option[String] = None,
      @arg(doc = "leave out the area and power columns (no cost flow; the clock is then --clock or --clock-ghz)") noCost: Flag,
      @arg(doc = "configurations run at once on this machine") jobs: Int = Runtime.getRuntime.availableProcessors,
      @arg(doc = "run each configuration as a task of a Slurm job array and wait for the merged result (docs/cluster.md)") slurm: Flag,
      @arg(doc = "Slurm partition for --slurm (default: the cluster's)") partition: Option[String] = None,
      @arg(doc = "internal: run configuration N of the list alone (a Slurm array task)") task: Option[Int] = None,
      @arg(doc = "internal: merge the configurations' results into the CSV and charts (the Slurm collect step)") collect: Flag,
      opts: RtlOptions
  ): Int = {
    val list = configs.map(parseConfigs).getOrElse(MapmParams.table48Configs)
    MapmError.check(list.nonEmpty, "sweep: no configurations given")
    MapmError.check(list.distinct.size == list.size, s"sweep: a configuration is listed twice in --configs")
    Slurm.checkOptions(name, jobs, slurm.value, partition, task, collect.value)
    opts.harness() // checks the memory model's options before any work
    val fixedClock = parseClock(clock)
    MapmError.check(!(noCost.value && clock.contains("fmax")), "sweep: --clock fmax needs the cost flow (drop --no-cost, or give GHz)")
    val work = workDir(opts)
    val log: String => Unit = l => System.err.println(s"mapm: $l")
    task match {
      case Some(i) =>
        MapmError.check(i >= 0 && i < list.size, s"sweep: --task $i is outside the ${list.size} configurations")
        runTask(opts, list(i), work.resolve("tasks").resolve(i.toString), work, log)
        0
      case None if slurm.value =>
        opts.check(list) // a scene or configuration error stops before anything is submitted
        // Each task reruns this sweep with the same options (not --slurm, --partition or --jobs).
        val taskArgs = Seq("--configs", list.map { case (t, s, a) => s"$t/$s/$a" }.mkString(",")) ++
          clock.toSeq.flatMap(c => Seq("--clock", c)) ++ (if (noCost.value) Seq("--no-cost") else Seq.empty) ++ Args.toArgs(opts)
        val rc = Slurm.run(name, taskArgs, list.size, partition, work.resolve("slurm"), log)
        if (rc != 0) MapmError.fail(s"sweep: the Slurm collect step ended with exit status $rc (logs in ${work.resolve("slurm")})")
        0
      case None =>
        if (!collect.value) runLocal(opts, list, jobs, work, log)
        report(opts, list, work, fixedClock, !noCost.value, log)
    }
  }

  /** The sweep's work folder (as [[RtlRun.setup]] names it). */
  def workDir(opts: RtlOptions): Path =
    Paths.get(opts.out).resolve(ModelRun.sceneName(Paths.get(opts.scene)) + (if (opts.arith == Arith.Online) "" else "-conv") + "-rtl")

  /** Runs the configurations `jobs` at a time on a frame prepared once; each leaves its result file. */
  def runLocal(opts: RtlOptions, list: Seq[(Int, Int, Int)], jobs: Int, work: Path, log: String => Unit): Unit = {
    val RtlRun.Setup(params, prep) = opts.setup(list)
    println(s"sweep of ${params.size} configurations on ${prep.config.file}, $jobs at once, ${opts.hw.describe}: ${prep.model.count} shader operations, ${prep.model.tsOps} TS ops" +
      (if (opts.fidelityOr() == mapm.params.Fidelity.Timing) "; SOAs as timing models (cycle-exact; colours from the model, not checked)" else ""))
    val pool = Executors.newFixedThreadPool(math.min(jobs, params.size))
    implicit val ec: ExecutionContext = ExecutionContext.fromExecutorService(pool)
    try {
      val runs = params.zip(list).map { case (p, c) =>
        Future(runOne(prep, p, c, opts, work, if (jobs == 1) log else (l: String) => log(s"[${p.counts.label}] $l"), progress = jobs == 1))
      }
      runs.foreach(Await.result(_, Duration.Inf))
    } finally pool.shutdown()
  }

  /** One configuration on a prepared frame: runs it, prints its line (after `prefix`), writes its result file. */
  private[cli] def runOne(prep: RtlRun.Prepared, p: MapmParams, c: (Int, Int, Int), opts: RtlOptions, work: Path, log: String => Unit,
                          progress: Boolean, prefix: String = ""): Unit = {
    val dir = SweepReport.configDir(work, c)
    val r = RtlRun.runConfig(prep, p, opts.harness(), dir, log, progress)
    val s = r.outcome.stats
    def orNaN(v: Option[Double]): Double = v.getOrElse(Double.NaN)
    println(f"$prefix${p.counts.label}%-8s ${if (r.passed) "PASS" else if (r.stopped) "STOPPED" else "FAIL"} cycles ${orNaN(s.map(_.cycles.toDouble))}%.0f " +
      f"SO/cycle ${orNaN(s.map(_.soPerCycle))}%.3f TS ops/cycle ${orNaN(s.flatMap(_.tsOpsPerCycle))}%.3f " +
      f"simulated ${orNaN(s.map(_.simulatedCyclesPerSecond))}%.0f cycles/s${if (r.passed) "" else ": " + r.failure}")
    SweepReport.writeResult(dir, SweepReport.TaskResult(p.counts.label, c._1, c._2, c._3, r.passed, if (r.passed) "" else r.failure,
      r.beside.map { case (k, v) => s"$k (beside the model)" -> v } ++ r.times))
  }

  /** A Slurm array task: prepares the frame in its own folder (the model is deterministic; no task
    * writes another's files) and runs one configuration into the shared work folder. */
  def runTask(opts: RtlOptions, c: (Int, Int, Int), own: Path, work: Path, log: String => Unit): Unit = {
    val RtlRun.Setup(Seq(p), prep) = opts.copy(out = own.toString).setup(Seq(c))
    runOne(prep, p, c, opts, work, log, progress = false)
  }

  /** The CSV and charts from the configurations' result files; fails when any configuration failed. */
  def report(opts: RtlOptions, list: Seq[(Int, Int, Int)], work: Path, fixedClock: Option[Double], withCost: Boolean,
             log: String => Unit): Int = {
    val rows = list.map(SweepReport.readRow(work, _))
    val cost = if (!withCost) None else Some(unitCost(opts, fixedClock, log))
    val clockGHz = cost.map(_.clockGHz).getOrElse(fixedClock.getOrElse(opts.clockGhz))
    cost.foreach(c => println(f"cost: ${c.soa.top} ${c.soa.areaUm2 / 1e6}%.4f mm^2, fmax ${c.soa.fmaxGHz}%.3f GHz; ${c.tsa.top} " +
      f"${c.tsa.areaUm2 / 1e6}%.4f mm^2, fmax ${c.tsa.fmaxGHz}%.3f GHz; clock ${c.clockGHz}%.3f GHz (${c.clockSource})"))
    val name = work.getFileName.toString.stripSuffix("-rtl")
    val outDir = Paths.get(opts.out)
    Files.createDirectories(outDir)
    val csv = outDir.resolve(s"$name-sweep.csv")
    Files.write(csv, SweepReport.csv(rows, cost, clockGHz).getBytes("UTF-8"))
    val charts = SweepReport.charts(outDir, name, name, rows, cost, clockGHz)
    (csv +: charts).foreach(f => println(s"wrote $f"))
    val failed = rows.filterNot(_.passed)
    if (failed.nonEmpty) MapmError.fail(s"sweep: ${failed.size} of ${rows.size} configurations failed: " +
      failed.map(r => s"${r.label} (${r.result.failure})").mkString("; "))
    0
  }

  /** The SOA's and TSA's figures in the sweep's format, g and arithmetic, and the clock: `fixed`, or the slower unit's fmax. */
  def unitCost(opts: RtlOptions, fixed: Option[Double], log: String => Unit): SweepReport.Cost = {
    val fmt = opts.format.orElse(ModelRun.loadScene(opts.scene).format).getOrElse(mapm.numerics.FloatFormat.fp32)
    val soa = UnitCostCache.get("soa", fmt, opts.g, opts.arith, log)
    val tsa = UnitCostCache.get("tsa", fmt, opts.g, opts.arith, log)
    val fmax = math.min(soa.fmaxGHz, tsa.fmaxGHz)
    SweepReport.Cost(soa, tsa, fixed.getOrElse(fmax), if (fixed.isDefined) "--clock" else s"fmax of the slower unit, the ${if (soa.fmaxGHz <= tsa.fmaxGHz) "SOA" else "TSA"}")
  }

  lazy val parser: ParserForMethods[_] = ParserForMethods(this)

  def run(args: Seq[String]): Int = Args.run(this, args)
}
