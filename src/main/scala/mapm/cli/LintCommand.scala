package mapm.cli

import mapm.pipeline.{Configure, Tuning}

import mainargs.{ParserForMethods, arg, main}
import mapm.MapmError
import mapm.numerics.FloatFormat
import mapm.params.{Hierarchy, MapmParams}
import mapm.sim.{Harness, Lint, MapmRtl}
import Args.{FloatFormatReader, HierarchyReader}

/** `mapm lint`: emits whole MAPMs (cached, as `render` does) and lints each with Verilator
  * (`--lint-only -Wall`). Prints each configuration's verdict and its first warnings; exit 0 only
  * when every one is clean. The default list is every shipped preset (Table 4.8's 24). */
object LintCommand extends Command {
  val name = "lint"
  val summary = "emit whole MAPMs and lint them with verilator -Wall (default: every shipped preset)"

  @main
  def lint(
      @arg(doc = "configurations TSM/SOM/SOA, comma separated (default: the 24 presets of Table 4.8)") configs: Option[String] = None,
      @arg(doc = "number format") format: FloatFormat = FloatFormat.fp32,
      @arg(name = "g", doc = "guard digits of the SOA's online units") g: Int = 3,
      @arg(doc = "memory hierarchy: scalable or table4.2 (docs/uncore.md)") hierarchy: Hierarchy = Hierarchy.Scalable
  ): Int = {
    val list = configs.map(SweepCommand.parseConfigs).getOrElse(MapmParams.table48Configs)
    MapmError.check(list.nonEmpty, "lint: no configurations given")
    val params = list.map { case (t, s, a) => Configure.of(t, s, a, format, g, tuning = Tuning(hierarchy = hierarchy)) }
    val t0 = System.nanoTime()
    val dirty = params.flatMap { p =>
      val t1 = System.nanoTime()
      val (dir, top) = MapmRtl.emit(p, l => System.err.println(s"mapm: $l"))
      val w = Lint.warnings(Harness.svFiles(dir), top)
      println(f"${p.counts.label}%-8s $top%-30s ${if (w.isEmpty) "clean" else s"${w.size} warnings"} (${(System.nanoTime() - t1) / 1e9}%.0f s)")
      w.take(5).foreach(m => println(s"  $m"))
      if (w.isEmpty) None else Some(p.counts.label)
    }
    println(f"lint: ${params.size - dirty.size} of ${params.size} configurations clean in ${(System.nanoTime() - t0) / 1e9}%.0f s")
    if (dirty.nonEmpty) MapmError.fail(s"lint: warnings in ${dirty.mkString(", ")}")
    0
  }

  lazy val parser: ParserForMethods[_] = ParserForMethods(this)

  def run(args: Seq[String]): Int = Args.run(this, args)
}
