package mapm.cli

import mapm.costflow._
import mapm.pipeline._

import java.nio.file.{Files, Path, Paths}
import mainargs.{Flag, ParserForMethods, arg, main}
import mapm.MapmError
import mapm.cost._
import mapm.numerics.{Arith, FloatFormat}
import Args.{ArithReader, FloatFormatReader}

/** `mapm cost`: clock, area and power of one unit (`--unit`) or of a whole MAPM configuration
  * (`--tsm --som --soa`), through the open flow of docs/cost.md: yosys synthesis to a Liberty
  * library (OSU 0.18 um by default), gate-level simulation of the netlist on real operations
  * (which checks it against the model and measures each net's switching activity), and OpenSTA
  * timing and power at each target clock. Writes `cost.json` and `cost.md` and prints the table.
  * `--arith conventional` costs the conventional SOA or TSA (or a whole conventional MAPM);
  * `--compare` costs both arithmetics of the SOA or TSA and compares them ([[CostCompare]]).
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
      @arg(doc = "output directory") out: String = "out/cost"
  ): Int = {
    Args.checkSeed(seed)
    val clocks = CostFlow.parseClocks(clock)
    MapmError.check(g >= 0 && g <= 8, s"cost: --g must be 0..8, got $g")
    MapmError.check(fpuWeight >= 0.5 && fpuWeight <= 100, s"cost: --fpu-weight must be 0.5..100, got $fpuWeight")
    MapmError.check(ops >= 64 && ops <= 10000000, s"cost: --ops must be 64..10000000, got $ops")
    MapmError.check(Seq("frame", "random").contains(stimulus), s"cost: --stimulus must be frame or random, got '$stimulus'")
    MapmError.check(abc == "both" || Synthesis.AbcScripts.contains(abc), s"cost: --abc must be plain, buffer or both, got '$abc'")
    val counts = Seq(tsm, som, soa)
    val libPath = lib.map(Paths.get(_))
    libPath.foreach(p => MapmError.check(Files.isRegularFile(p), s"cost: Liberty file $p not found"))
    MapmError.check(!compare.value || unit.forall(u => u == "soa" || u == "tsa"),
      "cost: --compare needs --unit soa or --unit tsa, or --tsm/--som/--soa for the whole MAPM")
    lazy val frameOps = CostFlow.frame(scene, format)
    /** Unit `u` in arithmetic `a`, its reports into `dir`. */
    def unitCost(u: String, a: Arith, dir: Path): UnitCost = {
      val cu = CostUnits(u, format, g, fpuWeight, a)
      val flow = CostFlow(libPath, clocks, abc, dir)
      val useFrame = stimulus == "frame" && cu.checksModel
      val frame = if (useFrame) Some(frameOps) else None
      val source = if (useFrame) s"SOs/TS ops of $scene"
        else if (cu.checksModel) s"random operations (seed $seed)" else s"random digit streams (seed $seed)"
      val online = a == Arith.Online
      val r = flow.unit(cu, format, if (Seq("soa", "mul", "div").contains(u) && online) Some(g) else None,
        CostUnits.ops(cu, format, g, frame, ops, seed, a), seed, source)
      print(r.markdown)
      println(s"wrote ${dir.resolve("cost.json")} and cost.md")
      r
    }
    (unit, counts.flatten.size) match {
      case (Some(u), 0) if compare.value =>
        val base = Paths.get(out)
        val costs = Arith.all.map(a => unitCost(u, a, base.resolve(a.name)))
        val c = CostCompare(u, format, costs(0), costs(1), CostUnits(u, format, g, fpuWeight).validRate)
        println(); print(c.markdown)
        c.write(base)
        println(s"wrote ${base.resolve("compare.json")} and compare.md")
        0
      case (Some(u), 0) =>
        unitCost(u, arith, Paths.get(out))
        0
      case (None, 3) if compare.value =>
        // Both arithmetics: their SOA and TSA through the flow, and the MAPM rendering the scene.
        val base = Paths.get(out)
        val figures = Arith.all.map { a =>
          val (soaCost, tsaCost) = (unitCost("soa", a, base.resolve(a.name).resolve("soa")), unitCost("tsa", a, base.resolve(a.name).resolve("tsa")))
          System.err.println(s"cost: rendering $scene through the $a ${tsm.get}/${som.get}/${soa.get} MAPM ...")
          val opts = RtlOptions(scene = scene, format = Some(format), g = g, arith = a, out = base.resolve(a.name).toString)
          val setup = opts.setup(Seq((tsm.get, som.get, soa.get)))
          val (p, prep) = (setup.params.head, setup.prep)
          val run = RtlRun.runConfig(prep, p, opts.harness(), prep.work, l => System.err.println(s"mapm: $l"))
          val s = run.outcome.stats.getOrElse(MapmError.fail(s"cost: the $a render wrote no statistics (${run.failure})"))
          val rgb = run.outcome.frame.getOrElse(MapmError.fail(s"cost: the $a render wrote no frame"))
          SystemFigures(a, mapm.sim.MapmRtl.topName(p), s.cycles, s.soIssued, p.counts.som * p.counts.soaPerSom, p.counts.tsm,
            soaCost, tsaCost, mapm.model.Metrics.psnr(rgb, RtlRun.reference(prep, opts.threads)), run.passed)
        }
        val c = SystemCompare(s"${tsm.get}/${som.get}/${soa.get}", format, scene, figures(0), figures(1))
        println(); print(c.markdown)
        c.write(base)
        println(s"wrote ${base.resolve("compare-system.json")} and compare-system.md")
        if (figures.forall(_.passed)) 0 else MapmError.fail("cost: a render failed its checks (see above)")
      case (None, 3) =>
        val base0 = mapm.pipeline.Configure.of(tsm.get, som.get, soa.get, format, g, arith = arith)
        val params = base0.copy(numbers = base0.numbers.copy(fpuStageWeight = fpuWeight))
        val base = Paths.get(out)
        val frame = if (stimulus == "frame") Some(CostFlow.frame(scene, format)) else None
        val source = if (stimulus == "frame") s"SOs/TS ops of $scene" else s"random (seed $seed)"
        val units = Seq("soa", "tsa").map { k =>
          val cu = CostUnits(k, format, g, fpuWeight, arith)
          System.err.println(s"cost: unit $k ...")
          val flow = CostFlow(libPath, clocks, abc, base.resolve(k))
          val (r, gl) = flow.unitWithActivity(cu, format, if (k == "soa" && arith == Arith.Online) Some(g) else None,
            CostUnits.ops(cu, format, g, frame, ops, seed, arith), seed, source)
          print(r.markdown + "\n")
          (r, gl)
        }
        val flow = CostFlow(libPath, clocks, abc, base.resolve("config"))
        val j = ConfigCost.run(flow, params, units(0)._1, units(1)._1, units(0)._2.meanActivity, base.resolve("config"),
          s => System.err.println(s"cost: $s"))
        Files.createDirectories(base)
        Files.write(base.resolve("cost.json"), ujson.write(j, indent = 2).getBytes("UTF-8"))
        val md = ConfigCost.markdown(j)
        Files.write(base.resolve("cost.md"), md.getBytes("UTF-8"))
        print(md)
        println(s"wrote ${base.resolve("cost.json")} and cost.md")
        0
      case (None, 0) => MapmError.fail("cost: give --unit U, or --tsm T --som S --soa A for a whole MAPM")
      case (Some(_), _) => MapmError.fail("cost: give either --unit or --tsm/--som/--soa, not both")
      case _ => MapmError.fail("cost: a whole MAPM needs all three of --tsm, --som and --soa")
    }
  }

  lazy val parser: ParserForMethods[_] = ParserForMethods(this)

  def run(args: Seq[String]): Int = Args.run(this, args)
}
