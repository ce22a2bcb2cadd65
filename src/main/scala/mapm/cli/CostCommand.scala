package mapm.cli

import java.nio.file.{Files, Path, Paths}
import mainargs.{ParserForMethods, arg, main}
import mapm.MapmError
import mapm.cost._
import mapm.model.{FloatFormat, Frame}
import mapm.sim.{Emit, Verilator, VerilatorPipe}
import Args.FloatFormatReader
import scala.concurrent.{Await, Future}
import scala.concurrent.duration.Duration
import scala.concurrent.ExecutionContext.Implicits.global

/** `mapm cost`: clock, area and power of one unit (`--unit`) or of a whole MAPM configuration
  * (`--tsm --som --soa`), through the open flow of docs/cost.md: yosys synthesis to a Liberty
  * library (OSU 0.18 um by default), gate-level simulation of the netlist on real operations
  * (which checks it against the model and measures each net's switching activity), and OpenSTA
  * timing and power at each target clock. Writes `cost.json` and `cost.md` and prints the table.
  */
object CostCommand extends Command {
  val name = "cost"
  val summary = "clock, area and power of a unit or a whole MAPM (yosys + OpenSTA, OSU 0.18 um)"

  @main
  def cost(
      @arg(doc = "unit: soa, tsa, cond, fadd, fmul, mul, div (or give --tsm/--som/--soa for a whole MAPM)") unit: Option[String] = None,
      @arg(doc = "Tree Search Modules of a whole MAPM") tsm: Option[Int] = None,
      @arg(doc = "Shader Operation Modules of a whole MAPM") som: Option[Int] = None,
      @arg(doc = "SOAs per SOM of a whole MAPM") soa: Option[Int] = None,
      @arg(doc = "float format: fp32, bf16, fp16, fp24, fp64 or E,M") format: FloatFormat = FloatFormat.fp32,
      @arg(name = "g", doc = "guard digits of the SOA's online units") g: Int = 3,
      @arg(doc = "target clocks in GHz, comma-separated") clock: String = CostFlow.defaultClocks.mkString(","),
      @arg(doc = "Liberty file (default: OSU 0.18 um, installed on first use)") lib: Option[String] = None,
      @arg(doc = "ABC script: plain, buffer, or both (keep the faster netlist)") abc: String = "both",
      @arg(doc = "operations for the gate-level simulation (activity and check)") ops: Int = 32768,
      @arg(doc = "operations from: frame (the scene's SOs / TS ops; mul and div always take random digits) or random (seeded bit patterns)") stimulus: String = "frame",
      @arg(doc = "scene whose operations drive the simulation") scene: String = "test-scenes/cornell-box/scene.json",
      @arg(doc = "seed of the valid pattern and of random operations") seed: Long = 1,
      @arg(doc = "output directory") out: String = "out/cost"
  ): Int = {
    val clocks = CostFlow.parseClocks(clock)
    MapmError.check(g >= 0 && g <= 8, s"cost: --g must be 0..8, got $g")
    MapmError.check(ops >= 64 && ops <= 10000000, s"cost: --ops must be 64..10000000, got $ops")
    MapmError.check(Seq("frame", "random").contains(stimulus), s"cost: --stimulus must be frame or random, got '$stimulus'")
    MapmError.check(abc == "both" || Synthesis.AbcScripts.contains(abc), s"cost: --abc must be plain, buffer or both, got '$abc'")
    val counts = Seq(tsm, som, soa)
    val libPath = lib.map(Paths.get(_))
    libPath.foreach(p => MapmError.check(Files.isRegularFile(p), s"cost: Liberty file $p not found"))
    (unit, counts.flatten.size) match {
      case (Some(u), 0) =>
        val cu = CostUnits(u, format, g)
        val flow = CostFlow(libPath, clocks, abc, Paths.get(out))
        val useFrame = stimulus == "frame" && cu.checksModel
        val frame = if (useFrame) Some(CostFlow.frame(scene, format)) else None
        val source = if (useFrame) s"SOs/TS ops of $scene"
          else if (cu.checksModel) s"random operations (seed $seed)" else s"random digit streams (seed $seed)"
        val r = flow.unit(cu, format, if (Seq("soa", "mul", "div").contains(u)) Some(g) else None,
          CostUnits.ops(cu, format, g, frame, ops, seed), seed, source)
        print(r.markdown)
        println(s"wrote ${Paths.get(out).resolve("cost.json")} and cost.md")
        0
      case (None, 3) =>
        val params = mapm.top.MapmParams.of(tsm.get, som.get, soa.get, format, g)
        val base = Paths.get(out)
        val frame = if (stimulus == "frame") Some(CostFlow.frame(scene, format)) else None
        val source = if (stimulus == "frame") s"SOs/TS ops of $scene" else s"random (seed $seed)"
        val units = Seq("soa", "tsa").map { k =>
          val cu = CostUnits(k, format, g)
          System.err.println(s"cost: unit $k ...")
          val flow = CostFlow(libPath, clocks, abc, base.resolve(k))
          val (r, gl) = flow.unitWithActivity(cu, format, if (k == "soa") Some(g) else None,
            CostUnits.ops(cu, format, g, frame, ops, seed), seed, source)
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

  def run(args: Seq[String]): Int = Args.run(ParserForMethods(this), args, name)
}

/** The cost flow of one unit, step by step (docs/cost.md). */
final case class CostFlow(lib: Option[Path], clocksGHz: Seq[Double], abc: String, out: Path) {
  private def log(s: String): Unit = System.err.println(s"cost: $s")
  private def secs(t0: Long): Double = (System.nanoTime() - t0) / 1e9

  lazy val libPath: Path = lib.getOrElse(CostTools.get.osu018Lib)
  lazy val library: Liberty.Library = Liberty.read(libPath)

  /** Synthesizes `top` with each ABC script asked for and keeps the netlist with the higher
    * fmax (timing alone, no activity needed). Returns it, each script's fmax and the seconds. */
  def synthesize(svFile: Path, top: String): (Synthesis.Result, Seq[(String, Double)], Double) = {
    val scripts = if (abc == "both") Synthesis.AbcScripts else Seq(abc)
    val delayPs = math.round(1000.0 / clocksGHz.max).toInt
    val (runs, seconds) = Synthesis.run(Seq(svFile), top, libPath, delayPs, scripts, out.resolve("synth"))
    val tried = runs.map { r =>
      Future {
        val f = Sta.run(Seq(r.verilog), top, libPath, Seq(clocksGHz.max), r.dir.resolve("sta"), Seq.empty, Seq.empty).fmaxGHz
        log(f"${r.abc} ABC script: fmax $f%.3f GHz")
        (r, f)
      }
    }.map(Await.result(_, Duration.Inf))
    (tried.maxBy(_._2)._1, tried.map { case (r, f) => r.abc -> f }, seconds)
  }

  def unit(u: CostUnit, format: FloatFormat, g: Option[Int], ops: IndexedSeq[UnitOp], seed: Long,
           source: String): UnitCost = unitWithActivity(u, format, g, ops, seed, source)._1

  /** [[unit]], with the gate-level run's outcome (its activities) beside the figures. */
  def unitWithActivity(u: CostUnit, format: FloatFormat, g: Option[Int], ops: IndexedSeq[UnitOp], seed: Long,
                       source: String): (UnitCost, GateLevel.Result) = {
    val t0 = System.nanoTime()
    log(s"emitting ${u.top} ...")
    val sv = Emit.toFile(u.module(), out.resolve("rtl"), s"${u.top}.sv", forSynthesis = true)
    val t1 = System.nanoTime()
    log(s"synthesizing ${u.top} (${if (abc == "both") "plain and buffering ABC scripts" else abc}) ...")
    val (syn, tried, _) = synthesize(sv, u.top)
    val t2 = System.nanoTime()
    val netlist = Netlist.read(syn.json, Some(u.top))
    val area = netlist.area(library)
    val rtl = if (Verilator.available) {
      log(s"building the RTL of ${u.top} in Verilator (for the gate-level check) ...")
      Some(VerilatorPipe.build(u.module(), CostTools.root.resolve("target/verilator-pipe")))
    } else None
    MapmError.check(rtl.isDefined || u.checksModel, s"cost: --unit ${u.kind} is checked against its RTL, and verilator is not installed")
    log(s"gate-level simulation of ${ops.length} operations ...")
    val gl = GateLevel.run(u, netlist, library, ops, seed, rtl)
    MapmError.check(gl.mismatches == 0,
      s"cost: the synthesized ${u.top} differs from the model or the RTL (${gl.mismatches} mismatches); first: ${gl.first.getOrElse("")}")
    val t3 = System.nanoTime()
    log(s"timing and power at ${clocksGHz.mkString(", ")} GHz ...")
    val sta = Sta.run(Seq(syn.verilog), u.top, libPath, clocksGHz, out.resolve("sta"), gl.pinActivity, gl.portActivity)
    val t4 = System.nanoTime()
    val crit = Sta.run(Seq(syn.verilog), u.top, libPath, Seq(sta.fmaxGHz), out.resolve("sta-fmax"), Seq.empty, Seq.empty).clocks.head
    // A flip-flop instance is named after the register its output carries.
    def point(p: String): String = netlist.cells.find(_.name == p).flatMap { c =>
      library.cells.get(c.cellType).filter(_.isSequential).flatMap(_.outputs.headOption).flatMap(o => c.pins.get(o.name))
        .map(n => s"$p (${netlist.describe(n)})")
    }.getOrElse(p)
    val r = UnitCost(u.kind, u.top, format.toString, g, libPath.getFileName.toString, syn.abc, sta.fmaxGHz,
      area.total, area.sequential, area.counts, sta.clocks,
      ujson.Obj("source" -> source, "validRate" -> u.validRate, "validRateFrom" -> u.validRateSource,
        "method" -> "zero-delay gate-level simulation of the netlist, 64 lanes; toggles per net per cycle",
        "cycles" -> gl.cycles.toDouble, "lanes" -> GateLevel.Lanes, "meanActivity" -> gl.meanActivity,
        "flopOutputActivity" -> gl.flopActivity),
      ujson.Obj("operations" -> ops.length, "modelChecked" -> gl.checked, "rtlChecked" -> gl.rtlChecked.toDouble,
        "rtl" -> gl.rtlNote, "mismatches" -> gl.mismatches),
      ujson.Obj("emit" -> (t1 - t0) / 1e9, "synthesis" -> (t2 - t1) / 1e9, "gateLevel" -> (t3 - t2) / 1e9,
        "sta" -> (t4 - t3) / 1e9, "total" -> secs(t0),
        "abcTried" -> ujson.Obj.from(tried.map { case (s, f) => s -> ujson.Num(f) })),
      point(crit.startPoint), point(crit.endPoint))
    r.write(out)
    (r, gl)
  }
}

object CostFlow {
  /** The default target clocks (GHz): a sweep around what OSU 0.18 um reaches. */
  val defaultClocks: Seq[Double] = Seq(0.1, 0.2, 0.3, 0.4, 0.5)

  def parseClocks(s: String): Seq[Double] = {
    val v = s.split(",").toSeq.map(_.trim).filter(_.nonEmpty).map(x =>
      x.toDoubleOption.getOrElse(MapmError.fail(s"cost: --clock takes GHz values separated by commas, got '$x'")))
    MapmError.check(v.nonEmpty && v.forall(c => c > 0 && c <= 20), s"cost: --clock values must be in (0, 20] GHz, got '$s'")
    v.distinct.sorted
  }

  /** The frame of `scene` in `format`, for operations that drive the simulation. */
  def frame(scene: String, format: FloatFormat): Frame = {
    val config = ModelRun.loadScene(scene)
    try Frame.prepare(config, format)
    catch { case e: MapmError => MapmError.fail(s"cost: cannot take operations from $scene in $format (${e.getMessage}); use --stimulus random") }
  }
}
