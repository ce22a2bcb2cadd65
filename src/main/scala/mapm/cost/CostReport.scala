package mapm.cost

import java.nio.charset.StandardCharsets
import java.nio.file.{Files, Path}

/** The figures of one synthesized unit, as `cost.json` and `cost.md` carry them.
  *
  * @param latency    the unit's latency in cycles (input to output)
  * @param areaUm2    total cell area; `seqAreaUm2` the flip-flops' part
  * @param cells      cell count per library cell
  * @param clocks     timing and power at each requested clock (power at the unit's activity)
  * @param activity   how the switching activity was obtained, and its averages
  * @param check      the gate-level check: operations simulated and mismatches found
  */
final case class UnitCost(unit: String, top: String, format: String, g: Option[Int], latency: Int, library: String,
                          abc: String, fmaxGHz: Double, areaUm2: Double, seqAreaUm2: Double,
                          cells: Map[String, Int], clocks: Seq[Sta.AtClock], activity: ujson.Obj,
                          check: ujson.Obj, seconds: ujson.Obj, criticalStart: String, criticalEnd: String) {
  def combAreaUm2: Double = areaUm2 - seqAreaUm2

  /** Dynamic energy per clock cycle (pJ) at the measured activity: OpenSTA's dynamic power is
    * this energy times the clock, at every clock. */
  def dynamicPjPerCycle: Double = clocks.head.dynamicMw / clocks.head.clockGHz
  /** Dynamic energy per operation (nJ) at the measured activity: a cycle's energy over the
    * operations a cycle carries (the gate-level run's valid rate, the unit's share of a 16/16/2
    * frame's cycles), so every idle cycle's clock and flip-flop energy is charged to the work. */
  def energyPerOpNj: Option[Double] =
    activity.value.get("validRate").flatMap(_.numOpt).filter(_ > 0).map(r => dynamicPjPerCycle / r / 1000)
  /** Dynamic power (mW) at clock `ghz`. */
  def dynamicMwAt(ghz: Double): Double = dynamicPjPerCycle * ghz
  /** With clock gates: the dynamic energy per cycle (pJ) were every gate's clock running in
    * every cycle ([[Sta.AtClock.ungatedDynamicMw]]). */
  def ungatedPjPerCycle: Option[Double] = clocks.head.ungatedDynamicMw.map(_ / clocks.head.clockGHz)

  def json: ujson.Obj = ujson.Obj(
    "unit" -> unit, "top" -> top, "format" -> format, "g" -> g.map(ujson.Num(_)).getOrElse(ujson.Null), "latency" -> latency,
    "library" -> library, "abc" -> abc, "fmaxGHz" -> fmaxGHz,
    "atFmax" -> ujson.Obj("clockGHz" -> fmaxGHz, "dynamicPowerMw" -> dynamicMwAt(fmaxGHz),
      "leakagePowerMw" -> clocks.head.leakageMw, "dynamicPjPerCycle" -> dynamicPjPerCycle),
    "energyPerOpNj" -> energyPerOpNj.map(ujson.Num(_)).getOrElse(ujson.Null),
    "ungatedDynamicPjPerCycle" -> ungatedPjPerCycle.map(ujson.Num(_)).getOrElse(ujson.Null),
    "areaUm2" -> areaUm2, "seqAreaUm2" -> seqAreaUm2, "combAreaUm2" -> combAreaUm2,
    "criticalPath" -> ujson.Obj("start" -> criticalStart, "end" -> criticalEnd),
    "cells" -> ujson.Obj.from(cells.toSeq.sortBy(_._1).map { case (k, v) => k -> ujson.Num(v) }),
    "clocks" -> ujson.Arr.from(clocks.map(c => ujson.Obj(
      "clockGHz" -> c.clockGHz, "slackMet" -> c.slackMet, "worstSlackNs" -> c.worstSlackNs,
      "criticalPath" -> ujson.Obj("start" -> c.startPoint, "end" -> c.endPoint, "arrivalNs" -> c.arrivalNs),
      "areaUm2" -> areaUm2, "seqAreaUm2" -> seqAreaUm2,
      "internalPowerMw" -> c.internalMw, "switchingPowerMw" -> c.switchingMw,
      "dynamicPowerMw" -> c.dynamicMw, "leakagePowerMw" -> c.leakageMw))),
    "activity" -> activity, "gateLevelCheck" -> check, "seconds" -> seconds)

  /** A table in the layout of the dissertation's Tables 4.3/4.4: per target clock, slack met,
    * total dynamic power, cell leakage, area. */
  def markdown: String = {
    val sb = new StringBuilder
    sb ++= s"$unit ($top), format $format${g.map(x => s", g = $x").getOrElse("")}, latency $latency cycles, library $library, ABC script $abc\n\n"
    sb ++= "| clock (GHz) | slack met? | worst slack (ns) | dynamic power (mW) | cell leakage (uW) | area (um^2) |\n"
    sb ++= "|---:|:---:|---:|---:|---:|---:|\n"
    for (c <- clocks)
      sb ++= f"| ${c.clockGHz}%.3f | ${if (c.slackMet) "yes" else "no"} | ${c.worstSlackNs}%.3f | ${c.dynamicMw}%.3f | ${c.leakageMw * 1e3}%.3f | $areaUm2%.0f |\n"
    sb ++= f"\nfmax $fmaxGHz%.3f GHz (critical path $criticalStart -> $criticalEnd); dynamic power at fmax " +
      f"${dynamicMwAt(fmaxGHz)}%.3f mW ($dynamicPjPerCycle%.1f pJ per cycle" +
      energyPerOpNj.fold("")(e => f", $e%.3f nJ per operation") + f"); area $areaUm2%.0f um^2 " +
      f"(sequential $seqAreaUm2%.0f, combinational $combAreaUm2%.0f), ${cells.values.sum} cells\n"
    for (u <- ungatedPjPerCycle; n <- activity.value.get("clockGates"); d <- activity.value.get("gateDutyMean"))
      sb ++= f"clock gates: ${n.num}%.0f, enabled ${d.num * 100}%.1f %% of the cycles on average; with every gate's clock running " +
        f"$u%.1f pJ per cycle\n"
    for (f <- activity.value.get("flopClocksPerCycle"); r <- activity.value.get("validRate"); n <- activity.value.get("flops"))
      sb ++= f"flip-flops: ${n.num}%.0f, clocked ${f.num}%.0f a cycle, ${f.num / r.num}%.0f per operation\n"
    sb ++= f"gate-level check: ${check("operations").num}%.0f operations, ${check("mismatches").num}%.0f mismatches; " +
      f"mean net activity ${activity("meanActivity").num}%.3f toggles/cycle\n"
    sb ++= "run time (s): " + Seq("emit", "synthesis", "gateLevel", "sta", "total").flatMap(k =>
      seconds.value.get(k).map(v => f"$k ${v.num}%.0f")).mkString(", ") + "\n"
    sb.toString
  }

  def write(dir: Path): Unit = {
    Files.createDirectories(dir)
    Files.write(dir.resolve("cost.json"), ujson.write(json, indent = 2).getBytes(StandardCharsets.UTF_8))
    Files.write(dir.resolve("cost.md"), markdown.getBytes(StandardCharsets.UTF_8))
  }
}
