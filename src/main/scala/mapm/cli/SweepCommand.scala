package mapm.cli

import mapm.evaluation.{Slurm, Sweep}

import mainargs.{Flag, ParserForMethods, arg, main}
import mapm.MapmError
import mapm.cli.Args.rtlOptionsParser
import mapm.params.MapmParams

/** `mapm sweep`: a design-space sweep over TSM/SOM/SOA configurations (default: the 24 of Table
  * 4.8) on one scene through the RTL ([[Sweep]]: the model side runs once, each configuration is
  * emitted, verilated and run with its cached builds). Every run is checked like `render`'s.
  *
  * Runs `--jobs` configurations at once, or each as a task of a Slurm job array (`--slurm`,
  * [[Slurm]]). Each run leaves `result.json` and `stats.json` in its folder; the CSV and charts
  * are made from those files alone ([[mapm.evaluation.SweepReport]]): `<scene>-sweep.csv` (cycles, SO/cycle, TS
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
    val settings = opts.settings()
    val work = settings.workDir
    val log: String => Unit = l => System.err.println(s"mapm: $l")
    task match {
      case Some(i) =>
        MapmError.check(i >= 0 && i < list.size, s"sweep: --task $i is outside the ${list.size} configurations")
        Sweep.runTask(settings, list(i), Sweep.taskDir(settings, i), log)
        0
      case None if slurm.value =>
        settings.check(list) // a scene or configuration error stops before anything is submitted
        // Each task reruns this sweep with the same options (not --slurm, --partition or --jobs).
        val taskArgs = Seq("--configs", list.map { case (t, s, a) => s"$t/$s/$a" }.mkString(",")) ++
          clock.toSeq.flatMap(c => Seq("--clock", c)) ++ (if (noCost.value) Seq("--no-cost") else Seq.empty) ++ Args.toArgs(opts)
        val rc = Slurm.run(name, taskArgs, list.size, partition, work.resolve("slurm"), log)
        if (rc != 0) MapmError.fail(s"sweep: the Slurm collect step ended with exit status $rc (logs in ${work.resolve("slurm")})")
        0
      case None =>
        if (!collect.value) Sweep.runLocal(settings, list, jobs, log)
        Sweep.report(settings, list, fixedClock, !noCost.value, log)
        0
    }
  }

  lazy val parser: ParserForMethods[_] = ParserForMethods(this)

  def run(args: Seq[String]): Int = Args.run(this, args)
}
