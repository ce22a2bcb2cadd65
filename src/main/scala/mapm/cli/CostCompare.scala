package mapm.cli

import java.nio.charset.StandardCharsets.UTF_8
import java.nio.file.{Files, Path}
import mapm.cost.UnitCost
import mapm.model.FloatFormat

/** The online unit against the conventional one under one flow (`cost --compare`), in the layout
  * of the dissertation's Tables 4.6 and 4.7: each design's fmax, area, and dynamic and leakage
  * power at a common clock both meet (the slower one's fmax) and at its own fmax; the ratios
  * online / conventional (Table 4.7 normalizes to the conventional design); and the dynamic
  * energy per cycle and per operation (the activity is the same frame's operations at the same
  * valid rate for both, so the energy per operation is the energy per cycle over that rate).
  */
final case class CostCompare(unit: String, format: FloatFormat, online: UnitCost, conventional: UnitCost, validRate: Double) {
  /** The common clock: the slower design's fmax. */
  val commonGHz: Double = online.fmaxGHz min conventional.fmaxGHz

  def fmaxRatio: Double = online.fmaxGHz / conventional.fmaxGHz
  def dynamicPowerRatio: Double = online.dynamicMwAt(commonGHz) / conventional.dynamicMwAt(commonGHz)
  def areaRatio: Double = online.areaUm2 / conventional.areaUm2
  def energyPerOpRatio: Double = online.dynamicPjPerCycle / conventional.dynamicPjPerCycle
  def leakageRatio: Double = online.clocks.head.leakageMw / conventional.clocks.head.leakageMw

  private def figures(c: UnitCost): ujson.Obj = ujson.Obj(
    "top" -> c.top, "latency" -> c.latency, "fmaxGHz" -> c.fmaxGHz, "areaUm2" -> c.areaUm2, "seqAreaUm2" -> c.seqAreaUm2,
    "atCommonClock" -> ujson.Obj("clockGHz" -> commonGHz, "dynamicPowerMw" -> c.dynamicMwAt(commonGHz),
      "leakagePowerMw" -> c.clocks.head.leakageMw),
    "atOwnFmax" -> ujson.Obj("clockGHz" -> c.fmaxGHz, "dynamicPowerMw" -> c.dynamicMwAt(c.fmaxGHz),
      "leakagePowerMw" -> c.clocks.head.leakageMw),
    "dynamicPjPerCycle" -> c.dynamicPjPerCycle, "dynamicPjPerOperation" -> c.dynamicPjPerCycle / validRate,
    "criticalPath" -> ujson.Obj("start" -> c.criticalStart, "end" -> c.criticalEnd))

  def json: ujson.Obj = ujson.Obj(
    "unit" -> unit, "format" -> format.toString, "library" -> online.library, "validRate" -> validRate,
    "commonClockGHz" -> commonGHz,
    "fmaxRatio" -> fmaxRatio, "dynamicPowerRatio" -> dynamicPowerRatio, "areaRatio" -> areaRatio,
    "energyPerOpRatio" -> energyPerOpRatio, "leakagePowerRatio" -> leakageRatio,
    "online" -> figures(online), "conventional" -> figures(conventional))

  def markdown: String = {
    val sb = new StringBuilder
    sb ++= s"$unit, format $format: online (${online.top}) against conventional (${conventional.top}), library ${online.library}\n\n"
    sb ++= "| | clock (GHz) | dynamic power (mW) | leakage (uW) | area (um^2) | latency (cycles) |\n|---|---:|---:|---:|---:|---:|\n"
    for ((name, c) <- Seq("online" -> online, "conventional" -> conventional); (what, ghz) <- Seq("common clock" -> commonGHz, "own fmax" -> c.fmaxGHz))
      sb ++= f"| $name, $what | $ghz%.3f | ${c.dynamicMwAt(ghz)}%.2f | ${c.clocks.head.leakageMw * 1e3}%.2f | ${c.areaUm2}%.0f | ${c.latency} |\n"
    sb ++= "\nNormalized to the conventional design (Table 4.7's layout; the dissertation's online/FloPoCo in brackets):\n\n"
    sb ++= "| | online | conventional |\n|---|---:|---:|\n"
    sb ++= f"| fmax | $fmaxRatio%.3f (3.5) | 1 |\n"
    sb ++= f"| dynamic power at the common clock | $dynamicPowerRatio%.3f (0.104) | 1 |\n"
    sb ++= f"| area | $areaRatio%.3f (1.799) | 1 |\n"
    sb ++= f"| dynamic energy per operation | $energyPerOpRatio%.3f | 1 |\n"
    sb ++= f"\nDynamic energy: online ${online.dynamicPjPerCycle}%.1f pJ per cycle (${online.dynamicPjPerCycle / validRate}%.1f per operation), " +
      f"conventional ${conventional.dynamicPjPerCycle}%.1f (${conventional.dynamicPjPerCycle / validRate}%.1f), at a valid rate of $validRate%.3f.\n"
    sb.toString
  }

  def write(dir: Path): Unit = {
    Files.createDirectories(dir)
    Files.write(dir.resolve("compare.json"), ujson.write(json, indent = 2).getBytes(UTF_8))
    Files.write(dir.resolve("compare.md"), markdown.getBytes(UTF_8))
  }
}
