package mapm.cli

import mapm.costflow._

import mapm.Slow
import java.nio.charset.StandardCharsets
import java.nio.file.{Files, Path, Paths}
import mapm.MapmError
import mapm.cost.{CostTools, Liberty, Netlist}
import mapm.numerics.FloatFormat
import org.scalatest.funsuite.AnyFunSuite

/** `mapm cost` on small units: the whole flow (synthesis, gate-level check, timing, power) on an
  * e3m3 TSA and an e5m4 SOA driven by seeded random operations; areas against this test's own sum
  * of Liberty cell areas over the netlist; the gate-level check catching a broken netlist; bad
  * input. The fp32 units run in the benchmark command `tools/mapm cost --unit soa|tsa` (docs/cost.md). */
@Slow
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
    // Energy per operation: a cycle's dynamic energy (power over clock) over the operations a cycle carries.
    val perCycle = clocks.head("dynamicPowerMw").num / clocks.head("clockGHz").num
    assert(math.abs(j("energyPerOpNj").num - perCycle / a("validRate").num / 1000) < 1e-9 * j("energyPerOpNj").num)
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

  test("cost --unit fadd at e3m2 with --fpu-weight 1: the deeper adder (10 stages) keeps the function on every operation") {
    val (out, j) = unitRun("fadd", "3,2", "--fpu-weight", "1")
    assert(j("top").str == "FAdd_e3m2_s10" && j("latency").num == 10, j("top").str)
    checkUnit(out, j)
  }

  test("cost --unit tsa --compare at e3m3: both TSAs keep their function; the ratios are those of the two reports") {
    tools()
    val out = Files.createTempDirectory("mapm-cost-compare")
    val (rc, text) = runCost("--unit", "tsa", "--format", "3,3", "--stimulus", "random", "--ops", "2048",
      "--clock", "0.05,0.1,0.2", "--compare", "--out", out.toString)
    assert(rc == 0 && text.contains("Normalized to the conventional design"), text)
    val on = ujson.read(Files.readAllBytes(out.resolve("online").resolve("cost.json")))
    val conv = ujson.read(Files.readAllBytes(out.resolve("conventional").resolve("cost.json")))
    checkUnit(out.resolve("online"), on)
    checkUnit(out.resolve("conventional"), conv) // the gate-level ConvTSA against ConvTsaModel
    assert(on("top").str == "TSA_e3m3_t16" && conv("top").str == "ConvTSA_e3m3_t16_a8", conv("top").str)
    val c = ujson.read(Files.readAllBytes(out.resolve("compare.json")))
    def close(a: Double, b: Double) = math.abs(a - b) <= 1e-9 * math.abs(b)
    assert(close(c("areaRatio").num, on("areaUm2").num / conv("areaUm2").num))
    assert(close(c("fmaxRatio").num, on("fmaxGHz").num / conv("fmaxGHz").num))
    assert(close(c("commonClockGHz").num, math.min(on("fmaxGHz").num, conv("fmaxGHz").num)))
    val pj = (x: ujson.Value) => x("atFmax")("dynamicPjPerCycle").num
    assert(close(c("energyPerOpRatio").num, pj(on) / pj(conv)) && close(c("dynamicPowerRatio").num, pj(on) / pj(conv)))
  }

  test("cost --unit fdiv at e4m3: the SRT divider keeps its function on every operation") {
    val (out, j) = unitRun("fdiv", "4,3")
    assert(j("top").str.startsWith("FDiv_e4m3_s"))
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

  /** A 4 x 3 Cornell-box frame of 100 photons, written into `dir`. */
  private def tinyScene(dir: Path): Path = {
    val scene = dir.resolve("tiny.json")
    Files.write(scene, (s"""{ "obj": "${mapm.model.TestScenes.cornellObj.toAbsolutePath}",
      |  "camera": { "position": [278, 273, -530], "direction": [0, 0, 1], "up": [0, 1, 0], "fov": 39.3 },
      |  "lights": [ { "type": "point", "position": [1, 25, 1], "power": [100000, 100000, 100000] } ],
      |  "width": 4, "height": 3, "finalGatherRays": 2, "photons": 100, "maxBounces": 3, "h": 100, "seed": 3 }""".stripMargin).getBytes("UTF-8"))
    scene
  }

  test("cost --tsm 1 --som 1 --soa 1 --compare at e5m4: both MAPMs render and pass; the system table follows the reports") {
    tools()
    assume(mapm.testutil.HostTools.onPath("verilator"), "verilator is not on PATH")
    val out = Files.createTempDirectory("mapm-cost-system")
    val scene = tinyScene(out)
    val (rc, text) = runCost("--tsm", "1", "--som", "1", "--soa", "1", "--format", "5,4", "--compare", "--scene", scene.toString,
      "--ops", "512", "--clock", "0.05,0.1", "--abc", "buffer", "--out", out.toString)
    assert(rc == 0 && text.contains("online / conventional"), text)
    val c = ujson.read(Files.readAllBytes(out.resolve("compare-system.json")))
    for (a <- Seq("online", "conventional")) {
      val sys = c(a)
      val soa = ujson.read(Files.readAllBytes(out.resolve(a).resolve("soa").resolve("cost.json")))
      val tsa = ujson.read(Files.readAllBytes(out.resolve(a).resolve("tsa").resolve("cost.json")))
      val rtlDir = Files.list(out.resolve(a)).toArray.map(_.asInstanceOf[Path]).filter(_.getFileName.toString.endsWith("-rtl"))
      assert(rtlDir.length == 1, rtlDir.mkString(", "))
      val stats = ujson.read(Files.readAllBytes(rtlDir.head.resolve("stats.json")))
      assert(sys("renderPassed").bool)
      assert(sys("cycles").num == stats("cycles").num && sys("soIssued").num == stats("soIssued").num)
      assert(sys("fmaxGHz").num == math.min(soa("fmaxGHz").num, tsa("fmaxGHz").num))
      assert(math.abs(sys("areaMm2").num * 1e6 - (soa("areaUm2").num + tsa("areaUm2").num)) < 1e-3)
      val pj = soa("atFmax")("dynamicPjPerCycle").num + tsa("atFmax")("dynamicPjPerCycle").num
      assert(math.abs(sys("frameEnergyMj").num - pj * sys("cycles").num * 1e-9) < 1e-9 * sys("frameEnergyMj").num)
    }
    assert(c("online")("soIssued").num == c("conventional")("soIssued").num, "the same SOs: the TSAs decide alike")
  }

  test("cost --tsm 1 --som 1 --soa 1 at e5m4: (a) is the unit figures, (b) every module's cells, the SRAM bits, the energy per SO over a frame") {
    tools()
    assume(mapm.testutil.HostTools.onPath("verilator"), "verilator is not on PATH")
    val out = Files.createTempDirectory("mapm-cost-config")
    // The frame whose counters give the energy per shader operation: the same MAPM, rendered bare.
    val scene = tinyScene(out)
    assert(RenderCommand.render(tsm = 1, som = 1, soa = 1, bare = mainargs.Flag(true),
      options = RtlOptions(scene = scene.toString, format = Some(FloatFormat(5, 4)), out = out.resolve("frame").toString, threads = 2)) == 0)
    val frame = out.resolve("frame").resolve(s"${mapm.pipeline.ModelRun.sceneName(scene)}-rtl-stats.json")
    val (rc, text) = runCost("--tsm", "1", "--som", "1", "--soa", "1", "--format", "5,4", "--stimulus", "random",
      "--ops", "512", "--clock", "0.05,0.1", "--abc", "buffer", "--so-bus", "ring", "--frame-stats", frame.toString, "--out", out.toString)
    assert(rc == 0 && text.contains("(a) 1 SOAs"), text)
    val j = ujson.read(Files.readAllBytes(out.resolve("cost.json")))
    val soa = ujson.read(Files.readAllBytes(out.resolve("soa").resolve("cost.json")))
    val tsa = ujson.read(Files.readAllBytes(out.resolve("tsa").resolve("cost.json")))
    val a = j("methodA")
    assert(math.abs(a("clocks")(0)("areaMm2").num * 1e6 - (soa("areaUm2").num + tsa("areaUm2").num)) < 1e-3)
    assert(a("fmaxGHz").num == math.min(soa("fmaxGHz").num, tsa("fmaxGHz").num))
    val dyn = soa("clocks")(0)("dynamicPowerMw").num + tsa("clocks")(0)("dynamicPowerMw").num
    assert(math.abs(a("clocks")(0)("dynamicPowerMw").num - dyn) < 1e-6 * dyn)

    // (b): every module's own cells (this test's Liberty areas) times its instances under the top.
    val b = j("methodB")
    val top = "Mapm_t1s1a1_e5m4_g3_ring"
    val net = ujson.read(Files.readAllBytes(out.resolve("config").resolve("synth").resolve("buffer").resolve("netlist.json")))("modules").obj
    def cellsOf(m: String): Seq[String] = net(m).obj.get("cells").map(_.obj.values.map(_("type").str).toSeq).getOrElse(Nil)
    def area(m: String): Double = cellsOf(m).map(t => areas.getOrElse(t, if (net.contains(t)) area(t) else fail(s"unknown cell $t"))).sum
    val logic = area(top)
    assert(math.abs(b("logicAreaMm2").num * 1e6 - logic) < 1e-6 * logic, s"(b) ${b("logicAreaMm2")} mm^2, own sum $logic um^2")
    assert(math.abs(b("areaByBlockMm2").obj.values.map(_.num).sum - b("logicAreaMm2").num) < 1e-9)
    // SRAM: every Memory array of the emitted Verilog, times its instances.
    val sv = new String(Files.readAllBytes(out.resolve("config").resolve("rtl").resolve(s"$top.sv")), StandardCharsets.UTF_8)
    val mods = """(?s)module\s+(\w+)\((.*?)endmodule""".r.findAllMatchIn(sv).map(m => m.group(1) -> m.group(2)).toMap
    val bits = mods.flatMap { case (n, body) =>
      """reg\s*\[(\d+):0\]\s*Memory\s*\[0:(\d+)\]""".r.findFirstMatchIn(body).map(m => n -> (m.group(1).toLong + 1) * (m.group(2).toLong + 1))
    }
    def memBits(m: String): Long = bits.getOrElse(m, 0L) + """(?m)^\s+(\w+)\s+\w+\s*\(""".r.findAllMatchIn(mods(m))
      .map(_.group(1)).filter(mods.contains).map(memBits).sum
    assert(bits.nonEmpty && b("sram")("bits").num == memBits(top).toDouble)
    // Energy per SO over the frame at method (b)'s fmax: the SOA's energy per operation (its own
    // gate-level run) times the frame's SOs; the rest's energy per cycle (dynamic power over its
    // clock) and leakage over the frame's time; the SRAM arrays' accesses and leakage.
    val e = b("energyPerSoNj")
    val st = ujson.read(Files.readAllBytes(frame))
    val (cyc, sos, f) = (st("cycles").num, st("soIssued").num, b("fmaxGHz").num)
    assert(e("cycles").num == cyc && e("shaderOperations").num == sos && e("clockGHz").num == f)
    assert(b("modules").arr.exists(m => m("module").str == soa("top").str && !m("ownLogicOnly").bool), "the SOA is kept and analysed whole")
    assert(e("soa")("module").str == soa("top").str && math.abs(e("soa")("nJPerSo").num - soa("energyPerOpNj").num) < 1e-12 * soa("energyPerOpNj").num)
    val c0 = b("clocks")(0)
    val soaPjPerCycle = soa("clocks")(0)("dynamicPowerMw").num / soa("clocks")(0)("clockGHz").num
    val logicNj = (c0("dynamicPowerMw").num / c0("clockGHz").num * cyc / 1000 - soaPjPerCycle * cyc / 1000 +
      soa("energyPerOpNj").num * sos + c0("leakagePowerMw").num * cyc / f / 1000) / sos
    assert(math.abs(e("logic").num - logicNj) < 1e-9 * logicNj, s"logic ${e("logic")} nJ, from the clocks and the SOA's report $logicNj")
    val sramLeakNj = b("sram")("leakageMw").num * cyc / f / 1000
    val sramDyn = e("sramByArray").obj.values.map(_("nJPerSo").num).sum
    assert(math.abs(e("sram").num - (sramDyn + sramLeakNj / sos)) < 1e-9 * e("sram").num)
    assert(math.abs(e("total").num - (e("logic").num + e("sram").num)) < 1e-12 * e("total").num)
    // The tags of the one SOP L1 bank are read every cycle.
    assert(e("sramByArray")("sopL1 tags")("reads").num == cyc && text.contains("energy per shader operation"))
    // Each part alone, then the whole netlist timed at once: no faster than its slowest part alone
    // (every part's paths are in it, with later inputs and real loads), and it sets fmax.
    val mins = b("modules").arr.map(_("fmaxGHz").num)
    assert(b("partsFmaxGHz").num == mins.min && b("fmaxGHz").num > 0)
    assert(b("crossPartTimed").bool, b("wholeTiming").toString)
    val whole = b("wholeTiming")
    assert(whole("configuration").str == "1/1/1" && whole("instances").num > 1000)
    assert(whole("fmaxGHz").num <= mins.min * (1 + 1e-3), s"whole ${whole("fmaxGHz")} GHz, slowest part ${mins.min}")
    assert(b("fmaxGHz").num == math.min(whole("fmaxGHz").num, mins.min))
    // The worst path's slack at the period found is within the search's tolerance, and that period was one of its trials.
    assert(whole("worstPaths")(0)("slackNs").num >= 0 && whole("worstPaths")(0)("slackNs").num <= 2e-3, whole.toString)
    assert(whole("trials").arr.exists(t => math.abs(t("periodNs").num - 1 / whole("fmaxGHz").num) < 1e-9 && t("worstSlackNs").num >= 0))
    for (c <- b("clocks").arr) {
      assert(c("slackMet").bool == (c("clockGHz").num <= b("fmaxGHz").num + 1e-9))
      assert(math.abs(c("dynamicByBlockMw").obj.values.map(_.num).sum - c("dynamicPowerMw").num) < 1e-6 * c("dynamicPowerMw").num)
    }
    assert(Files.isRegularFile(out.resolve("cost.md")))
    // The boundary check: every kept module checked; the ring bus states a registered boundary and has no path; the
    // memory arbiter (a combinational round-robin: a request's valid decides the others' ready) has paths.
    val bounds = b("boundaries")("modules").arr.map(m => m("module").str -> m).toMap
    val kept = net.keySet.filter(m => m != top && cellsOf(m).nonEmpty && !bits.contains(m) && !areas.contains(m))
    assert(bounds.keySet == kept.toSet, s"checked ${bounds.keySet}, kept $kept")
    val ring = bounds.filter(_._1.startsWith("RingBus")).values.toSeq
    assert(ring.size == 1 && ring.head("registered").bool && ring.head("paths").num == 0)
    val arb = bounds.filter(_._1.startsWith("MemArbiter")).values
    assert(arb.nonEmpty && arb.forall(m => !m("registered").bool && m("paths").num > 0))
  }

  test("bad input: one-line errors") {
    def err(args: String*): String = intercept[MapmError](CostCommand.run(args)).getMessage
    assert(err("--unit", "nope").contains("unknown unit 'nope'"))
    assert(err("--unit", "tsa", "--clock", "fast").contains("--clock"))
    assert(err("--unit", "tsa", "--clock", "0").contains("--clock"))
    assert(err("--unit", "tsa", "--lib", "/nonexistent/x.lib").contains("Liberty file /nonexistent/x.lib not found"))
    assert(err("--unit", "tsa", "--stimulus", "noise").contains("--stimulus"))
    assert(err("--unit", "tsa", "--abc", "fancy").contains("--abc"))
    assert(err("--unit", "cond", "--fpu-weight", "0.1").contains("--fpu-weight must be 0.5..100"))
    assert(err("--tsm", "2").contains("all three"))
    assert(err("--unit", "cond", "--compare").contains("--compare needs --unit soa or --unit tsa"))
    assert(err("--unit", "fadd", "--arith", "conventional").contains("--arith applies to the soa and tsa units"))
    assert(err("--unit", "tsa", "--arith", "floating").contains("online or conventional"))
    assert(err().contains("give --unit"))
    assert(err("--unit", "tsa", "--tsm", "1", "--som", "1", "--soa", "1").contains("not both"))
    assert(err("--unit", "soa", "--format", "5,2").contains("at least 4 fraction bits"))
    assert(err("--unit", "tsa", "--format", "3,3", "--stimulus", "frame").contains("--stimulus random"))
    assert(err("--unit", "tsa", "--frame-stats", "x.json").contains("--frame-stats applies to a whole MAPM"))
    assert(err("--tsm", "1", "--som", "1", "--soa", "1", "--frame-stats", "/nonexistent/s.json").contains("frame statistics /nonexistent/s.json not found"))
    // Statistics of another configuration: named, before any synthesis.
    val other = Files.createTempFile("mapm-frame", ".json")
    val stats = mapm.testutil.StatsFixture.json(cycles = 10, so = 5, ts = 3, bytes = 64, soqMisses = 1)
    stats("top") = "Mapm_t2s2a2_e8m23_g3_ring"
    Files.write(other, ujson.write(stats).getBytes("UTF-8"))
    val wrong = err("--tsm", "1", "--som", "1", "--soa", "1", "--frame-stats", other.toString)
    assert(wrong.contains("t2s2a2") && wrong.contains("Mapm_t1s1a1_e8m23_g3_ring"), wrong)
  }
}
