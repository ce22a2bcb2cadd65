package mapm.cli

import java.nio.file.{Files, Paths}
import mainargs.{ParserForMethods, arg, main}
import mapm.MapmError
import mapm.cli.Args.rtlOptionsParser
import mapm.sim.HarnessStats
import mapm.params.MapmParams

/** `mapm sweep`: a design-space sweep over TSM/SOM/SOA configurations (default: the 24 of Table
  * 4.8) on one scene through the RTL ([[RtlRun]]: the model side runs once, each configuration is
  * emitted, verilated and run with its cached builds). Every run is checked like `render`'s.
  *
  * Writes `<scene>-sweep.csv` (one row per configuration: cycles, SO/cycle, TS ops/cycle, speed-up
  * over the first configuration, hit rate per cache, GB/s, simulation wall time and simulated cycles
  * per second, result) and two bar charts
  * in the style of Figures 4.9 and 4.12: `<scene>-sweep-so-per-cycle.png` and
  * `<scene>-sweep-speedup.png`. */
object SweepCommand extends Command {
  val name = "sweep"
  val summary = "design-space sweep over TSM/SOM/SOA configurations through the RTL: CSV and charts"
  val caches: Seq[String] = Seq("tsL1", "tsL2", "soq", "sopL1", "sopL2")

  /** "1/1/2,2/1/2" into triples; a [[MapmError]] naming a bad entry. */
  def parseConfigs(s: String): Seq[(Int, Int, Int)] =
    s.split(',').map(_.trim).filter(_.nonEmpty).toSeq.map { c =>
      c.split('/').map(_.trim.toIntOption) match {
        case Array(Some(t), Some(m), Some(a)) => (t, m, a)
        case _ => MapmError.fail(s"sweep: --configs entry '$c' is not TSM/SOM/SOA (e.g. 16/16/2)")
      }
    }

  @main
  def sweep(
      @arg(doc = "configurations TSM/SOM/SOA, comma separated (default: the 24 of Table 4.8)") configs: Option[String] = None,
      opts: RtlOptions
  ): Int = {
    val list = configs.map(parseConfigs).getOrElse(MapmParams.table48Configs)
    MapmError.check(list.nonEmpty, "sweep: no configurations given")
    val harness = opts.harness()
    val RtlRun.Setup(params, prep) = opts.setup(list)
    println(s"sweep of ${params.size} configurations on ${prep.config.file}: ${prep.model.count} shader operations, ${prep.model.tsOps} TS ops" +
      (if (opts.fidelity == mapm.params.Fidelity.Timing) "; SOAs as timing models (cycle-exact; colours from the model, not checked)" else ""))
    def orNaN(v: Option[Double]): Double = v.getOrElse(Double.NaN)
    val runs = params.map { p =>
      val dir = prep.work.resolve(s"sweep-${p.counts.tsm}-${p.counts.som}-${p.counts.soaPerSom}")
      val r = RtlRun.runConfig(prep, p, harness, dir, l => System.err.println(s"mapm: $l"))
      val s = r.outcome.stats
      println(f"${p.counts.label}%-8s ${if (r.passed) "PASS" else "FAIL"} cycles ${orNaN(s.map(_.cycles.toDouble))}%.0f " +
        f"SO/cycle ${orNaN(s.map(_.soPerCycle))}%.3f TS ops/cycle ${orNaN(s.flatMap(_.tsOpsPerCycle))}%.3f " +
        f"simulated ${orNaN(s.map(_.simulatedCyclesPerSecond))}%.0f cycles/s${if (r.passed) "" else ": " + r.failure}")
      r
    }
    def cycles(r: RtlRun.ConfigRun): Option[Long] = r.outcome.stats.map(_.cycles)
    def cell(v: Option[Double]): String = v.filter(x => !x.isNaN).map(x => f"$x%.6g").getOrElse("")
    def stat(r: RtlRun.ConfigRun)(field: HarnessStats => Double): String = cell(r.outcome.stats.map(field))
    val speedups = runs.map(r => for (b <- cycles(runs.head); c <- cycles(r) if c > 0) yield b.toDouble / c)
    val header = (Seq("config", "tsm", "som", "soa", "cycles", "so_per_cycle", "ts_ops_per_cycle", "speedup") ++
      caches.map(c => s"hit_rate_$c") ++ Seq("gb_per_s", "sim_wall_s", "sim_cycles_per_s", "fidelity", "result")).mkString(",")
    val rows = runs.zip(speedups).map { case (r, sp) =>
      (Seq(r.p.counts.label, r.p.counts.tsm.toString, r.p.counts.som.toString, r.p.counts.soaPerSom.toString,
        cycles(r).map(_.toString).getOrElse(""), stat(r)(_.soPerCycle), cell(r.outcome.stats.flatMap(_.tsOpsPerCycle)), cell(sp)) ++
        caches.map(c => cell(r.outcome.stats.flatMap(_.caches.get(c)).map(_.hitRate))) ++
        Seq(stat(r)(_.gbPerSecond), stat(r)(_.wallSeconds), stat(r)(_.simulatedCyclesPerSecond), r.p.sim.fidelity.name, if (r.passed) "PASS" else "FAIL")).mkString(",")
    }
    val outDir = Paths.get(opts.out)
    Files.createDirectories(outDir)
    val csv = outDir.resolve(s"${prep.name}-sweep.csv")
    Files.write(csv, (header +: rows).mkString("", "\n", "\n").getBytes("UTF-8"))
    val labels = runs.map(_.p.counts.label)
    val soChart = outDir.resolve(s"${prep.name}-sweep-so-per-cycle.png")
    BarChart.write(soChart, s"Shader operations per cycle (${prep.name}, ${prep.frame.format})", "SO / cycle",
      labels.zip(runs.map(r => orNaN(r.outcome.stats.map(_.soPerCycle)))))
    val spChart = outDir.resolve(s"${prep.name}-sweep-speedup.png")
    BarChart.write(spChart, s"Speed-up over ${labels.head} (${prep.name})", "speed-up", labels.zip(speedups.map(_.getOrElse(Double.NaN))))
    Seq(csv, soChart, spChart).foreach(f => println(s"wrote $f"))
    val failed = runs.filterNot(_.passed)
    if (failed.nonEmpty) MapmError.fail(s"sweep: ${failed.size} of ${runs.size} configurations failed: " +
      failed.map(r => s"${r.p.counts.label} (${r.failure})").mkString("; "))
    0
  }

  def run(args: Seq[String]): Int = Args.run(ParserForMethods(this), args, name)
}
