package mapm.cli

import java.nio.file.{Files, Paths}
import mainargs.{ParserForMethods, arg, main}
import mapm.MapmError
import mapm.model.{FloatFormat, Parallel}
import mapm.sim.Harness
import mapm.params.MapmParams
import Args.FloatFormatReader

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
      @arg(doc = "scene description file (JSON)") scene: String = RenderCommand.defaultScene,
      @arg(doc = "configurations TSM/SOM/SOA, comma separated (default: the 24 of Table 4.8)") configs: Option[String] = None,
      @arg(doc = "number format (default: the scene's, else fp32)") format: Option[FloatFormat] = None,
      @arg(name = "g", doc = "guard digits of the SOA's online units") g: Int = 3,
      @arg(doc = "memory latency in cycles") latency: Int = 100,
      @arg(doc = "memory bandwidth in bytes per cycle") bandwidth: Double = 14.0,
      @arg(doc = "clock for the GB/s figure, in GHz") clockGhz: Double = 1.5,
      @arg(doc = "seed of the memory's response reordering") seed: Long = 1,
      @arg(doc = "threads of the Verilator model (a separate build; 1 is fastest on this design, see docs/harness.md)") simThreads: Int = 1,
      @arg(doc = "stop a run with FAIL after this many cycles (0: no limit)") maxCycles: Long = 0,
      @arg(doc = "output folder") out: String = "out",
      @arg(doc = "worker threads of the model") threads: Int = Parallel.defaultThreads
  ): Int = {
    val list = configs.map(parseConfigs).getOrElse(MapmParams.table48Configs)
    MapmError.check(list.nonEmpty, "sweep: no configurations given")
    val fmt = format.orElse(ModelRun.loadScene(scene).format).getOrElse(FloatFormat.fp32)
    val params = list.map { case (t, s, a) => MapmParams.of(t, s, a, fmt, g) }
    val opts = Harness.RunOptions(latency, bandwidth, seed, maxCycles, clockGhz, simThreads = simThreads)
    val prep = RtlRun.prepare(scene, Some(fmt), g, out, threads)
    println(s"sweep of ${params.size} configurations on ${prep.config.file}: ${prep.model.count} shader operations, ${prep.model.tsOps} TS ops")
    val runs = params.map { p =>
      val dir = prep.work.resolve(s"sweep-${p.counts.tsm}-${p.counts.som}-${p.counts.soaPerSom}")
      val r = RtlRun.runConfig(prep, p, opts, dir, l => System.err.println(s"mapm: $l"))
      println(f"${p.counts.label}%-8s ${if (r.passed) "PASS" else "FAIL"} cycles ${r.stat("cycles").getOrElse(Double.NaN)}%.0f " +
        f"SO/cycle ${r.stat("soPerCycle").getOrElse(Double.NaN)}%.3f TS ops/cycle ${r.stat("tsOpsPerCycle").getOrElse(Double.NaN)}%.3f " +
        f"simulated ${r.stat("simulatedCyclesPerSecond").getOrElse(Double.NaN)}%.0f cycles/s${if (r.passed) "" else ": " + r.failure}")
      r
    }
    val base = runs.head.stat("cycles")
    def cell(v: Option[Double]): String = v.filter(x => !x.isNaN).map(x => f"$x%.6g").getOrElse("")
    def whole(v: Option[Double]): String = v.filter(x => !x.isNaN).map(x => f"$x%.0f").getOrElse("")
    def hitRate(r: RtlRun.ConfigRun, c: String): Option[Double] =
      r.outcome.stats.flatMap(_.obj.get("caches")).flatMap(_.obj.get(c)).flatMap(_.obj.get("hitRate")).flatMap(_.numOpt)
    val speedups = runs.map(r => for (b <- base; c <- r.stat("cycles") if c > 0) yield b / c)
    val header = (Seq("config", "tsm", "som", "soa", "cycles", "so_per_cycle", "ts_ops_per_cycle", "speedup") ++
      caches.map(c => s"hit_rate_$c") ++ Seq("gb_per_s", "sim_wall_s", "sim_cycles_per_s", "result")).mkString(",")
    val rows = runs.zip(speedups).map { case (r, sp) =>
      (Seq(r.p.counts.label, r.p.counts.tsm.toString, r.p.counts.som.toString, r.p.counts.soaPerSom.toString, whole(r.stat("cycles")),
        cell(r.stat("soPerCycle")), cell(r.stat("tsOpsPerCycle")), cell(sp)) ++ caches.map(c => cell(hitRate(r, c))) ++
        Seq(cell(r.stat("gbPerSecond")), cell(r.stat("wallSeconds")), cell(r.stat("simulatedCyclesPerSecond")),
          if (r.passed) "PASS" else "FAIL")).mkString(",")
    }
    val outDir = Paths.get(out)
    Files.createDirectories(outDir)
    val csv = outDir.resolve(s"${prep.name}-sweep.csv")
    Files.write(csv, (header +: rows).mkString("", "\n", "\n").getBytes("UTF-8"))
    val labels = runs.map(_.p.counts.label)
    val soChart = outDir.resolve(s"${prep.name}-sweep-so-per-cycle.png")
    BarChart.write(soChart, s"Shader operations per cycle (${prep.name}, ${fmt})", "SO / cycle",
      labels.zip(runs.map(_.stat("soPerCycle").getOrElse(Double.NaN))))
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
