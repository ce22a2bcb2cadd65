package mapm.costflow

import mapm.pipeline._

import java.nio.file.Path
import mapm.MapmError
import mapm.cost._
import mapm.model.Frame
import mapm.numerics.FloatFormat
import mapm.sim.{Emit, Verilator, VerilatorPipe}
import scala.concurrent.{Await, Future}
import scala.concurrent.duration.Duration
import scala.concurrent.ExecutionContext.Implicits.global

/** The cost flow of one unit, step by step (docs/cost.md): emit, synthesize with each ABC script
  * and keep the faster netlist, simulate it at gate level on the operations (checking it against
  * the model and the RTL, measuring activity), then OpenSTA timing and power at each clock.
  *
  * @param lib       the Liberty file (default: OSU018, installed on first use)
  * @param clocksGHz the target clocks; the fastest sets ABC's delay target
  * @param abc       `plain`, `buffer` or `both`
  * @param out       where the netlists, logs, `cost.json` and `cost.md` go
  */
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
    val (runs, seconds) = SynthesisCache.run(Seq(svFile), top, libPath, delayPs, scripts, out.resolve("synth"))
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
      Some(VerilatorPipe.build(u.module()))
    } else None
    MapmError.check(rtl.isDefined || u.checksModel, s"cost: --unit ${u.kind} is checked against its RTL, and verilator is not installed")
    log(s"gate-level simulation of ${ops.length} operations ...")
    val gl = GateLevel.run(u, netlist, library, ops, seed, rtl)
    MapmError.check(gl.mismatches == 0,
      s"cost: the synthesized ${u.top} differs from the model or the RTL (${gl.mismatches} mismatches); first: ${gl.first.getOrElse("")}")
    val t3 = System.nanoTime()
    log(s"timing and power at ${clocksGHz.mkString(", ")} GHz ...")
    val sta = Sta.run(Seq(syn.verilog), u.top, libPath, clocksGHz, out.resolve("sta"), gl.pinActivity, gl.portActivity,
      gated = gl.gatedLevels, stopPins = gl.gateStopPins)
    val t4 = System.nanoTime()
    // The path that limits fmax: the worst at the clock nearest it (at a slow clock a clock gate's
    // half-cycle check can be the worst path without limiting anything).
    val crit = sta.clocks.minBy(c => math.abs(c.worstSlackNs))
    // A flip-flop instance is named after the register its output carries.
    def point(p: String): String = netlist.cells.find(_.name == p).flatMap { c =>
      library.cells.get(c.cellType).filter(_.isSequential).flatMap(_.outputs.headOption).flatMap(o => c.pins.get(o.name))
        .map(n => s"$p (${netlist.describe(n)})")
    }.getOrElse(p)
    val r = UnitCost(u.kind, u.top, format.toString, g, u.latency, libPath.getFileName.toString, syn.abc, sta.fmaxGHz,
      area.total, area.sequential, area.counts, sta.clocks,
      ujson.Obj("source" -> source, "validRate" -> u.validRate, "validRateFrom" -> u.validRateSource,
        "method" -> "zero-delay gate-level simulation of the netlist, 64 lanes; toggles per net per cycle",
        "cycles" -> gl.cycles.toDouble, "lanes" -> GateLevel.Lanes, "meanActivity" -> gl.meanActivity,
        "flopOutputActivity" -> gl.flopActivity, "clockGates" -> gl.gateDuties.size,
        "gateDutyMean" -> (if (gl.gateDuties.isEmpty) 0.0 else gl.gateDuties.sum / gl.gateDuties.size),
        "flops" -> gl.flops, "flopClocksPerCycle" -> gl.flopClocksPerCycle),
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
