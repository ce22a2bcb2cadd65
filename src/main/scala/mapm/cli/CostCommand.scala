package mapm.cli

import mapm.costflow._

import java.nio.file.{Files, Paths}
import mainargs.{Flag, ParserForMethods, arg, main}
import mapm.MapmError
import mapm.cost._
import mapm.numerics.{Arith, FloatFormat}
import Args.{ArithReader, FloatFormatReader, hwOptionsParser}

/** `mapm cost`: clock, area and power of one unit (`--unit`) or of a whole MAPM configuration
  * (`--tsm --som --soa`), through the open flow of docs/cost.md: yosys synthesis to a Liberty
  * library (OSU 0.18 um by default), gate-level simulation of the netlist on real operations
  * (which checks it against the model and measures each net's switching activity), and OpenSTA
  * timing and power at each target clock. Writes `cost.json` and `cost.md` and prints the table.
  * `--arith conventional` costs the conventional SOA or TSA (or a whole conventional MAPM);
  * `--compare` costs both arithmetics of the SOA or TSA and compares them ([[CostCompare]]).
  * The measuring is [[CostRun]]'s.
  */
object CostCommand extends Command {
  val name = "cost"
  val summary = "clock, area and power of a unit or a whole MAPM (yosys + OpenSTA, OSU 0.18 um)"

  @main
  def cost(
      @arg(doc = "unit: soa, tsa, cond, fadd, fmul, fdiv, mul, div (or give --tsm/--som/--soa for a whole MAPM)") unit: Option[String] = None,
      @arg(doc = "Tree Search Modules of a whole MAPM") tsm: Option[Int] = None,
      @arg(doc = "Shader Operation Modules of a whole MAPM") som: Option[Int] = None,
      @arg(doc = "SOAs per SOM of a whole MAPM") soa: Option[Int] = None,
      @arg(doc = "float format") format: FloatFormat = FloatFormat.fp32,
      @arg(name = "g", doc = "guard digits of the SOA's online units") g: Int = 3,
      @arg(doc = "arithmetic of the SOA and TSA: online or conventional") arith: Arith = Arith.Online,
      @arg(doc = "cost the soa or tsa unit in both arithmetics and compare them (Tables 4.6 and 4.7; compare.json); with --tsm/--som/--soa, both MAPMs rendering --scene through the RTL (compare-system.json)") compare: Flag,
      @arg(name = "fpu-weight", doc = "logic per pipeline stage of the conventional FP units (cond, fadd, fmul, the SOA's cond check), about one full adder per unit; smaller is deeper (docs/fpu.md)") fpuWeight: Double = mapm.params.NumberParams.DefaultFpuStageWeight,
      @arg(doc = "target clocks in GHz, comma-separated") clock: String = CostFlow.defaultClocks.mkString(","),
      @arg(doc = "Liberty file (default: OSU 0.18 um, installed on first use)") lib: Option[String] = None,
      @arg(doc = "ABC script: plain, buffer, or both (keep the faster netlist)") abc: String = "both",
      @arg(doc = "operations for the gate-level simulation (activity and check)") ops: Int = 32768,
      @arg(doc = "operations from: frame (the scene's SOs / TS ops; mul and div always take random digits) or random (seeded bit patterns)") stimulus: String = "frame",
      @arg(doc = "scene whose operations drive the simulation") scene: String = "test-scenes/cornell-box/scene.json",
      @arg(doc = "seed of the valid pattern and of random operations") seed: Long = 1,
      @arg(name = "frame-stats", doc = "a render's stats.json of the same whole MAPM: energy per shader operation over that frame, logic and SRAM (cost.json methodB.energyPerSoNj)") frameStats: Option[String] = None,
      @arg(doc = "output directory") out: String = "out/cost",
      hw: HwOptions
  ): Int = {
    Args.checkSeed(seed)
    val clocks = CostFlow.parseClocks(clock)
    MapmError.check(g >= 0 && g <= 8, s"cost: --g must be 0..8, got $g")
    MapmError.check(fpuWeight >= 0.5 && fpuWeight <= 100, s"cost: --fpu-weight must be 0.5..100, got $fpuWeight")
    MapmError.check(ops >= 64 && ops <= 10000000, s"cost: --ops must be 64..10000000, got $ops")
    MapmError.check(CostRun.Stimuli.contains(stimulus), s"cost: --stimulus must be ${CostRun.Stimuli.mkString(" or ")}, got '$stimulus'")
    MapmError.check(abc == "both" || Synthesis.AbcScripts.contains(abc), s"cost: --abc must be plain, buffer or both, got '$abc'")
    val counts = Seq(tsm, som, soa)
    val libPath = lib.map(Paths.get(_))
    libPath.foreach(p => MapmError.check(Files.isRegularFile(p), s"cost: Liberty file $p not found"))
    MapmError.check(!compare.value || unit.forall(u => u == "soa" || u == "tsa"),
      "cost: --compare needs --unit soa or --unit tsa, or --tsm/--som/--soa for the whole MAPM")
    MapmError.check(frameStats.isEmpty || (counts.forall(_.isDefined) && !compare.value),
      "cost: --frame-stats applies to a whole MAPM (--tsm/--som/--soa) without --compare")
    // Stage gating is inside the SOA (and the cond check): it applies to those units too.
    val tuned = hw.tuning.describe.filterNot(t => t == "no-soa-stage-gate" && unit.forall(u => u == "soa" || u == "cond"))
    MapmError.check(unit.isEmpty || tuned.isEmpty,
      s"cost: --${tuned.headOption.getOrElse("").takeWhile(_ != '=')} applies to a whole MAPM (--tsm/--som/--soa), not to --unit")
    val run = CostRun(format, g, fpuWeight, libPath, clocks, abc, ops, stimulus == "frame", scene, seed, Paths.get(out), hw.tuning)
    (unit, counts.flatten) match {
      case (Some(u), Seq()) if compare.value => run.compareUnits(u); 0
      case (Some(u), Seq()) => run.unit(u, arith); 0
      case (None, Seq(t, s, a)) if compare.value => run.compareSystems((t, s, a)); 0
      case (None, Seq(t, s, a)) => run.config((t, s, a), arith, frameStats.map(Paths.get(_))); 0
      case (None, Seq()) => MapmError.fail("cost: give --unit U, or --tsm T --som S --soa A for a whole MAPM")
      case (Some(_), _) => MapmError.fail("cost: give either --unit or --tsm/--som/--soa, not both")
      case _ => MapmError.fail("cost: a whole MAPM needs all three of --tsm, --som and --soa")
    }
  }

  lazy val parser: ParserForMethods[_] = ParserForMethods(this)

  def run(args: Seq[String]): Int = Args.run(this, args)
}
