package mapm.cli

import java.nio.charset.StandardCharsets
import java.nio.file.{Files, Path, Paths}
import mapm.MapmError
import mapm.cost.{CostTools, Liberty, Netlist}
import mapm.model.FloatFormat
import org.scalatest.funsuite.AnyFunSuite

/** `mapm cost` on small units: the whole flow (synthesis, gate-level check, timing, power) on an
  * e3m3 TSA and an e5m4 SOA driven by seeded random operations; areas against this test's own sum
  * of Liberty cell areas over the netlist; the gate-level check catching a broken netlist; bad
  * input. The fp32 units run in the benchmark command `tools/mapm cost --unit soa|tsa` (docs/cost.md). */
class CostCommandSpec extends AnyFunSuite {
  private def tools(): CostTools.Paths3 = CostTools.available.fold(
    why => cancel(s"cost tools (yosys, OpenSTA, OSU 0.18 um cells) unavailable: $why"), identity)

  private def runCost(args: String*): (Int, String) = {
    val buf = new java.io.ByteArrayOutputStream
    val rc = Console.withOut(buf)(CostCommand.run(args))
    (rc, buf.toString(StandardCharsets.UTF_8))
  }

  /** This test's own Liberty reading: cell name -> area, by a regular expression over the text. */
  private lazy val areas: Map[String, Double] = {
    val text = new String(Files.readAllBytes(tools().osu018Lib), StandardCharsets.ISO_8859_1)
    """cell\s*\((\w+)\)\s*\{[^}]*?\barea\s*:\s*([0-9.eE+-]+)""".r.findAllMatchIn(text).map(m => m.group(1) -> m.group(2).toDouble).toMap
  }
  /** The area of a yosys JSON netlist's cells, summed by this test. */
  private def ownArea(json: Path, top: String): Double = {
    val j = ujson.read(Files.readAllBytes(json))
    j("modules")(top)("cells").obj.values.map(c => areas(c("type").str)).sum
  }

  private def unitRun(unit: String, fmt: String, extra: String*): (Path, ujson.Value) = {
    tools()
    val out = Files.createTempDirectory(s"mapm-cost-$unit")
    val (rc, text) = runCost(Seq("--unit", unit, "--format", fmt, "--stimulus", "random", "--ops", "2048",
      "--clock", "0.05,0.1,0.2", "--out", out.toString) ++ extra: _*)
    assert(rc == 0)
    assert(text.contains("| clock (GHz) | slack met?"), text)
    (out, ujson.read(Files.readAllBytes(out.resolve("cost.json"))))
  }

  private def checkUnit(out: Path, j: ujson.Value): Unit = {
    assert(j("gateLevelCheck")("operations").num == 2048 && j("gateLevelCheck")("mismatches").num == 0)
    val top = j("top").str
    val json = out.resolve("synth").resolve(j("abc").str).resolve("netlist.json")
    val own = ownArea(json, top)
    assert(math.abs(j("areaUm2").num - own) < 1e-6 * own, s"reported area ${j("areaUm2").num}, own sum $own")
    val yosys = """Chip area for (?:top )?module '\\?""" + top + """': ([0-9.eE+-]+)"""
    val stat = new String(Files.readAllBytes(json.resolveSibling("stat.txt")), StandardCharsets.UTF_8)
    assert(math.abs(yosys.r.findFirstMatchIn(stat).get.group(1).toDouble - own) < 1e-6 * own, "yosys stat agrees")
    val clocks = j("clocks").arr
    assert(clocks.map(_("clockGHz").num) == Seq(0.05, 0.1, 0.2))
    for (c <- clocks) {
      assert(c("slackMet").bool == (c("worstSlackNs").num >= 0))
      assert(c("slackMet").bool == (c("clockGHz").num <= j("fmaxGHz").num + 1e-6), s"slack at ${c("clockGHz")} against fmax ${j("fmaxGHz")}")
      assert(c("dynamicPowerMw").num > 0 && c("leakagePowerMw").num > 0)
    }
    val a = j("activity")
    assert(a("meanActivity").num > 0 && a("meanActivity").num < 1 && a("cycles").num > 0)
    assert(Files.isRegularFile(out.resolve("cost.md")))
  }

  test("cost --unit tsa at e3m3: synthesis keeps the function on every operation; figures consistent") {
    val (out, j) = unitRun("tsa", "3,3")
    assert(j("unit").str == "tsa" && j("format").str == FloatFormat(3, 3).toString)
    checkUnit(out, j)
  }

  test("cost --unit soa at e5m4, g = 3: synthesis keeps the function on every operation; figures consistent") {
    val (out, j) = unitRun("soa", "5,4", "--g", "3", "--abc", "buffer")
    assert(j("g").num == 3 && j("abc").str == "buffer")
    checkUnit(out, j)
  }

  test("the gate-level check finds a netlist that synthesis did not keep") {
    val (out, j) = unitRun("tsa", "3,3", "--abc", "plain")
    val lib = Liberty.read(tools().osu018Lib)
    val nl = Netlist.read(out.resolve("synth").resolve("plain").resolve("netlist.json"), Some(j("top").str))
    // Swap every NAND2X1 for a NOR2X1: same pins, another function.
    val broken = nl.copy(cells = nl.cells.map(c => if (c.cellType == "NAND2X1") c.copy(cellType = "NOR2X1") else c))
    assert(broken.cells.count(_.cellType == "NOR2X1") > nl.cells.count(_.cellType == "NOR2X1"))
    val fmt = FloatFormat(3, 3)
    val u = CostUnits("tsa", fmt, 0)
    val ops = CostUnits.ops(u, fmt, 0, None, 512, 5)
    assert(GateLevel.run(u, nl, lib, ops, 5).mismatches == 0)
    assert(GateLevel.run(u, broken, lib, ops, 5).mismatches > 0)
  }

  test("bad input: one-line errors") {
    def err(args: String*): String = intercept[MapmError](CostCommand.run(args)).getMessage
    assert(err("--unit", "nope").contains("unknown unit 'nope'"))
    assert(err("--unit", "tsa", "--clock", "fast").contains("--clock"))
    assert(err("--unit", "tsa", "--clock", "0").contains("--clock"))
    assert(err("--unit", "tsa", "--lib", "/nonexistent/x.lib").contains("Liberty file /nonexistent/x.lib not found"))
    assert(err("--unit", "tsa", "--stimulus", "noise").contains("--stimulus"))
    assert(err("--unit", "tsa", "--abc", "fancy").contains("--abc"))
    assert(err("--tsm", "2").contains("all three"))
    assert(err().contains("give --unit"))
    assert(err("--unit", "tsa", "--tsm", "1", "--som", "1", "--soa", "1").contains("not both"))
    assert(err("--unit", "soa", "--format", "5,2").contains("at least 4 fraction bits"))
    assert(err("--unit", "tsa", "--format", "3,3", "--stimulus", "frame").contains("--stimulus random"))
  }
}
