package mapm.costflow

import mapm.pipeline.ModelRun

import java.nio.charset.StandardCharsets.UTF_8
import java.nio.file.{Files, Path}

import mapm.MapmError
import mapm.numerics.{Arith, FloatFormat}
import mapm.cost.CostTools
import mapm.sim.{BuildCache, Harness, MapmRtl}

/** The SOA's and TSA's cost figures for cost-aware sweeps, by the dissertation's method (Table
  * 4.9: unit figures times counts). Each unit goes through the cost flow ([[CostFlow]], the same
  * defaults as `tools/mapm cost --unit soa|tsa`) once per format, guard digits and arithmetic, and
  * the result is kept in the [[mapm.sim.BuildCache]] (kind `cost-units`, `cost.json`); the key covers
  * the flow's settings, the generator and cost-flow sources and the tools' versions, so a sweep, its later runs and `evaluate`
  * never synthesize the same unit twice. The operations come from the default scene's frame
  * (the Table 4.8 Cornell box) in the format, or seeded random ones where the format cannot hold
  * that frame. */
object UnitCostCache {
  /** What a sweep and the precision study need of a unit: fmax, area, dynamic energy per cycle at
    * its measured activity and per operation (NaN in a report written before it was kept), leakage. */
  final case class Figures(unit: String, top: String, fmaxGHz: Double, areaUm2: Double, dynamicPjPerCycle: Double,
                           leakageMw: Double, stimulus: String, file: Path, energyPerOpNj: Double = Double.NaN) {
    def dynamicMwAt(ghz: Double): Double = dynamicPjPerCycle * ghz
    def json: ujson.Obj = ujson.Obj("unit" -> unit, "top" -> top, "fmaxGHz" -> fmaxGHz, "areaUm2" -> areaUm2,
      "atFmax" -> ujson.Obj("dynamicPjPerCycle" -> dynamicPjPerCycle, "leakagePowerMw" -> leakageMw),
      "activity" -> ujson.Obj("source" -> stimulus),
      "energyPerOpNj" -> (if (energyPerOpNj.isNaN) ujson.Null else ujson.Num(energyPerOpNj)))
  }

  /** The flow settings (as `cost --unit` defaults them). */
  val ops = 32768
  val seed = 1L
  private val costSources = Seq("CostFlow.scala", "CostUnits.scala", "GateLevel.scala")

  /** The cached figures of `unit` (soa or tsa), running the flow on a miss (minutes: the fp32 SOA about 8). */
  def get(unit: String, format: FloatFormat, g: Int, arith: Arith, log: String => Unit): Figures = {
    MapmError.check(unit == "soa" || unit == "tsa", s"cost: unit costs of a sweep are soa or tsa, got '$unit'")
    val cu = CostUnits(unit, format, g, mapm.params.NumberParams.DefaultFpuStageWeight, arith)
    val srcDir = Harness.root.resolve("src/main/scala/mapm/costflow")
    val sources = costSources.map(f => f + new String(Files.readAllBytes(srcDir.resolve(f)), UTF_8))
    val inputs = Seq(cu.top, unit, format.toString, g.toString, arith.name, CostFlow.defaultClocks.mkString(","), "both",
      ops.toString, seed.toString, ModelRun.defaultScene, MapmRtl.hardwareSourceHash) ++ sources ++ Seq(CostTools.versions)
    val dir = BuildCache.entry("cost-units", cu.top, inputs, d => Files.isRegularFile(d.resolve("cost.json"))) { tmp =>
      log(s"cost of the $unit ${cu.top} through the cost flow (once; cached in ${BuildCache.root.resolve("cost-units")}) ...")
      val frame = try Some(CostFlow.frame(Harness.root.resolve(ModelRun.defaultScene).toString, format)) catch { case _: MapmError => None }
      val source = if (frame.isDefined) s"SOs/TS ops of ${ModelRun.defaultScene}" else s"random operations (seed $seed)"
      val flow = CostFlow(None, CostFlow.defaultClocks, "both", tmp)
      val online = arith == Arith.Online
      flow.unit(cu, format, if (unit == "soa" && online) Some(g) else None, CostUnits.ops(cu, format, g, frame, ops, seed, arith), seed, source)
    }
    read(unit, dir.resolve("cost.json"))
  }

  /** Reads a unit's `cost.json` (as [[mapm.cost.UnitCost.json]] writes it). */
  def read(unit: String, file: Path): Figures = {
    val j = try ujson.read(Files.readAllBytes(file)) catch { case e: Exception => MapmError.fail(s"$file: not a unit cost report (${e.getMessage})") }
    parse(unit, j, file)
  }

  /** The figures of a unit cost report `j` (a `cost.json`, or [[Figures.json]]) read from `file`. */
  def parse(unit: String, j: ujson.Value, file: Path): Figures = {
    try Figures(unit, j("top").str, j("fmaxGHz").num, j("areaUm2").num, j("atFmax")("dynamicPjPerCycle").num,
      j("atFmax")("leakagePowerMw").num, j("activity")("source").str, file,
      j.obj.get("energyPerOpNj").filter(_ != ujson.Null).map(_.num).getOrElse(Double.NaN))
    catch { case e: NoSuchElementException => MapmError.fail(s"$file: not a unit cost report (${e.getMessage})") }
  }
}
