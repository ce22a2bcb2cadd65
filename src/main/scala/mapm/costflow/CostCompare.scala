package mapm.costflow

import java.nio.charset.StandardCharsets.UTF_8
import java.nio.file.{Files, Path}
import mapm.cost.UnitCost
import mapm.numerics.{Arith, FloatFormat}

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

/** One arithmetic's MAPM rendering a frame, costed by the dissertation's method (unit figures
  * times counts): its cycles from the RTL render, its SOA and TSA from the cost flow.
  *
  * @param psnr the indirect image's PSNR against float64 */
final case class SystemFigures(arith: Arith, top: String, cycles: Long, soIssued: Long, soas: Int, tsas: Int,
                               soa: UnitCost, tsa: UnitCost, psnr: Double, passed: Boolean) {
  /** The slower unit's fmax: the clock of the whole by this method. */
  def fmaxGHz: Double = soa.fmaxGHz min tsa.fmaxGHz
  def soPerCycle: Double = soIssued.toDouble / cycles
  def frameMs: Double = cycles / (fmaxGHz * 1e9) * 1e3
  def areaMm2: Double = (soas * soa.areaUm2 + tsas * tsa.areaUm2) / 1e6
  /** Dynamic energy per cycle of all units (pJ), at the activity of the Cornell frame's operations. */
  def pjPerCycle: Double = soas * soa.dynamicPjPerCycle + tsas * tsa.dynamicPjPerCycle
  def dynamicMwAtFmax: Double = pjPerCycle * fmaxGHz
  def frameEnergyMj: Double = pjPerCycle * cycles * 1e-9
  def json: ujson.Obj = ujson.Obj("arith" -> arith.name, "top" -> top, "cycles" -> cycles.toDouble, "soIssued" -> soIssued.toDouble,
    "soPerCycle" -> soPerCycle, "fmaxGHz" -> fmaxGHz, "frameMs" -> frameMs, "areaMm2" -> areaMm2,
    "dynamicMwAtFmax" -> dynamicMwAtFmax, "frameEnergyMj" -> frameEnergyMj,
    "psnrDb" -> (if (psnr.isInfinite) ujson.Str("inf") else ujson.Num(psnr)), "renderPassed" -> passed,
    "soa" -> soa.top, "tsa" -> tsa.top)
}

/** The online and the conventional MAPM side by side (`cost --tsm T --som S --soa A --compare`). */
final case class SystemCompare(label: String, format: FloatFormat, scene: String, online: SystemFigures, conventional: SystemFigures) {
  private def both = Seq(online, conventional)
  def json: ujson.Obj = ujson.Obj("configuration" -> label, "format" -> format.toString, "scene" -> scene,
    "method" -> "unit figures x counts (dissertation Table 4.9); cycles from the RTL render",
    "online" -> online.json, "conventional" -> conventional.json,
    "ratios" -> ujson.Obj("cycles" -> online.cycles.toDouble / conventional.cycles, "fmax" -> online.fmaxGHz / conventional.fmaxGHz,
      "frameTime" -> online.frameMs / conventional.frameMs, "area" -> online.areaMm2 / conventional.areaMm2,
      "frameEnergy" -> online.frameEnergyMj / conventional.frameEnergyMj))

  def markdown: String = {
    val sb = new StringBuilder
    sb ++= s"MAPM $label, format $format, $scene: online against conventional (unit figures x counts; cycles from the RTL)\n\n"
    sb ++= "| | " + both.map(_.top).mkString(" | ") + " | online / conventional |\n|---|---:|---:|---:|\n"
    def row(name: String, f: SystemFigures => Double, fmt: Double => String): Unit =
      sb ++= s"| $name | ${both.map(x => fmt(f(x))).mkString(" | ")} | ${f"${f(online) / f(conventional)}%.3f"} |\n"
    row("cycles", _.cycles.toDouble, v => f"$v%,.0f")
    row("SO per cycle", _.soPerCycle, v => f"$v%.3f")
    row("fmax, the slower unit (MHz)", _.fmaxGHz * 1e3, v => f"$v%.0f")
    row("frame time at fmax (ms)", _.frameMs, v => f"$v%.3f")
    row("area of the units (mm^2)", _.areaMm2, v => f"$v%.1f")
    row("dynamic power at fmax (mW)", _.dynamicMwAtFmax, v => f"$v%,.0f")
    row("frame energy (mJ)", _.frameEnergyMj, v => f"$v%.2f")
    row("PSNR against float64 (dB)", _.psnr, v => f"$v%.2f")
    sb ++= s"\nrenders: ${both.map(x => s"${x.arith} ${if (x.passed) "PASS (every SO exact, frame bit-equal)" else "FAIL"}").mkString(", ")}\n"
    sb.toString
  }

  def write(dir: Path): Unit = {
    Files.createDirectories(dir)
    Files.write(dir.resolve("compare-system.json"), ujson.write(json, indent = 2).getBytes(UTF_8))
    Files.write(dir.resolve("compare-system.md"), markdown.getBytes(UTF_8))
  }
}
