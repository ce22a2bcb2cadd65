package mapm.cost

import mapm.Slow
import java.nio.charset.StandardCharsets
import java.nio.file.{Files, Path}
import org.scalatest.funsuite.AnyFunSuite

/** OpenSTA through [[Sta]] on hand-written OSU 0.18 um netlists, against bounds read from the
  * Liberty file by this test's own code (a few regular expressions, not [[Liberty]]). */
@Slow
class StaSpec extends AnyFunSuite {
  import StaSpec.CellData
  private def tools(): CostTools.Paths3 = CostTools.available.fold(
    why => cancel(s"cost tools (yosys, OpenSTA, OSU 0.18 um cells) unavailable: $why"), identity)

  private def cell(name: String): CellData = {
    val text = new String(Files.readAllBytes(tools().osu018Lib), StandardCharsets.ISO_8859_1)
    val start = text.indexOf(s"cell ($name)")
    assert(start >= 0, s"$name not in the library")
    val end = text.indexOf("\ncell (", start + 1) match { case -1 => text.length; case e => e }
    val body = text.substring(start, end)
    CellData("""area\s*:\s*([0-9.eE+-]+)""".r.findFirstMatchIn(body).get.group(1).toDouble,
      """cell_leakage_power\s*:\s*([0-9.eE+-]+)""".r.findFirstMatchIn(body).get.group(1).toDouble, body)
  }

  private def write(text: String): Path = {
    val f = Files.createTempDirectory("mapm-sta").resolve("net.v")
    Files.write(f, text.getBytes(StandardCharsets.UTF_8))
    f
  }
  private def register(n: Int): Path = write(
    s"module reg$n(clock, d, q);\n  input clock;\n  input [${n - 1}:0] d;\n  output [${n - 1}:0] q;\n" +
      (0 until n).map(i => s"  DFFPOSX1 r$i (.CLK(clock), .D(d[$i]), .Q(q[$i]));\n").mkString + "endmodule\n")
  /** K inverters in a row from input a to output y, and one more inverter hanging on y, so that
    * every inverter on the path drives one INVX1 input (a load inside the Liberty tables). */
  private def chain(k: Int): Path = write(
    s"module chain$k(clock, a, y);\n  input clock;\n  input a;\n  output y;\n  wire dangling;\n" +
      (1 until k).map(i => s"  wire n$i;\n").mkString +
      (0 until k).map { i =>
        val in = if (i == 0) "a" else s"n$i"; val out = if (i == k - 1) "y" else s"n${i + 1}"
        s"  INVX1 u$i (.A($in), .Y($out));\n"
      }.mkString + "  INVX1 load (.A(y), .Y(dangling));\nendmodule\n")
  /** k INVX1 cells in a chain from net `from` to net `to`, their nets and cells named after `p`,
    * with the wires between them declared. */
  private def invChain(from: String, to: String, k: Int, p: String): String =
    (0 until k).map { i =>
      val in = if (i == 0) from else s"$p$i"; val out = if (i == k - 1) to else s"$p${i + 1}"
      (if (i < k - 1) s"  wire $p${i + 1};\n" else "") + s"  INVX1 ${p}u$i (.A($in), .Y($out));\n"
    }.mkString

  private def sta(net: Path, top: String, clocks: Seq[Double], pins: Seq[(String, Sta.Activity)] = Nil,
                  ports: Seq[(String, Sta.Activity)] = Nil) =
    Sta.run(Seq(net), top, tools().osu018Lib, clocks, net.getParent.resolve("sta"), pins, ports)

  test("a chain of K inverters: delay within the INVX1 table bounds times K") {
    val inv = cell("INVX1")
    for (k <- Seq(1, 5, 20)) {
      val r = sta(chain(k), s"chain$k", Seq(0.1))
      val arrival = r.clocks.head.arrivalNs
      // The first inverter sees an ideal input (slew 0, below the tables' first index), so only
      // the other K - 1 are bound from below.
      assert(arrival >= (k - 1) * inv.delays.min - 1e-9 && arrival <= k * inv.delays.max + 1e-9,
        s"K = $k: arrival $arrival ns outside [${(k - 1) * inv.delays.min}, ${k * inv.delays.max}]")
      assert(arrival > 0)
      assert(math.abs(r.clocks.head.worstSlackNs - (10.0 - arrival)) < 1e-3, "slack is the period less the path")
      assert(math.abs(1.0 / r.fmaxGHz - arrival) < 2e-3, s"fmax ${r.fmaxGHz} GHz against a path of $arrival ns")
    }
  }

  test("a register of N flip-flops synthesized by yosys: N DFFPOSX1 cells, area N times the Liberty cell's") {
    val dff = cell("DFFPOSX1")
    for (n <- Seq(1, 8, 33)) {
      val r = YosysSynth(s"module r$n(input clock, input [${n - 1}:0] d, output reg [${n - 1}:0] q);\n" +
        "  always @(posedge clock) q <= d;\nendmodule\n", s"r$n")
      val area = r.netlist.area(Liberty.read(tools().osu018Lib))
      assert(area.counts == Map("DFFPOSX1" -> n))
      assert(math.abs(area.total - n * dff.area) < 1e-9 && area.sequential == area.total)
    }
  }

  test("a register of N flip-flops: leakage is the Liberty sum; zero data activity leaves the clock's energy only") {
    val dff = cell("DFFPOSX1")
    val n = 16
    val net = register(n)
    val zero = Sta.Activity(0, 0.5)
    val pins = (0 until n).flatMap(i => Seq(s"r$i/D" -> zero, s"r$i/Q" -> zero))
    val ports = (0 until n).map(i => s"d[$i]" -> zero)
    val f = 0.5
    val r = sta(net, s"reg$n", Seq(f), pins, ports).clocks.head
    assert(math.abs(r.leakageMw - n * dff.leakageNw * 1e-6) < 1e-9, s"leakage ${r.leakageMw} mW")
    // Per flip-flop and cycle: the CLK pin's rise and fall energies (pJ) and at most the clock net's C V^2.
    val perCycle = r.dynamicMw / f / n
    val capPf = dff.pinCap("CLK")
    val lo = dff.riseEnergy.min + dff.fallEnergy.min
    val hi = dff.riseEnergy.max + dff.fallEnergy.max + capPf * 1.8 * 1.8
    assert(perCycle >= lo - 1e-9 && perCycle <= hi + 1e-9, s"$perCycle pJ per flip-flop cycle outside [$lo, $hi]")
    // Still clock only whatever the data's duty, and data that moves costs more.
    val r2 = sta(net, s"reg$n", Seq(f), pins.map { case (p, _) => p -> Sta.Activity(0, 0.9) },
      ports.map { case (p, _) => p -> Sta.Activity(0, 0.9) }).clocks.head
    assert(math.abs(r2.dynamicMw - r.dynamicMw) < 1e-9)
    val busy = Sta.Activity(0.5, 0.5)
    val r3 = sta(net, s"reg$n", Seq(f), pins.map { case (p, _) => p -> busy }, ports.map { case (p, _) => p -> busy }).clocks.head
    assert(r3.dynamicMw > r.dynamicMw * 1.01, s"${r3.dynamicMw} mW with moving data against ${r.dynamicMw} mW")
  }

  test("dynamic power is proportional to the clock at a fixed activity per cycle; leakage does not move") {
    val n = 8
    val act = Sta.Activity(0.3, 0.5)
    val pins = (0 until n).flatMap(i => Seq(s"r$i/D" -> act, s"r$i/Q" -> act))
    val ports = (0 until n).map(i => s"d[$i]" -> act)
    val rs = sta(register(n), s"reg$n", Seq(0.25, 0.5, 1.0), pins, ports).clocks
    for (Seq(a, b) <- rs.sliding(2)) {
      assert(b.dynamicMw > a.dynamicMw)
      assert(math.abs(b.dynamicMw / a.dynamicMw - b.clockGHz / a.clockGHz) < 1e-4, s"${a.dynamicMw} -> ${b.dynamicMw} mW")
      assert(b.leakageMw == a.leakageMw)
    }
  }

  test("flip-flops behind a clock gate cost about what the same flip-flops on the clock port cost (no 3000x slew)") {
    val n = 1000
    def shift(gated: Boolean): Path = write(
      s"module sr(clock, en, d, q);\n  input clock;\n  input en;\n  input d;\n  output q;\n  wire gclk;\n" +
        (0 until n).map(i => s"  wire s$i;\n").mkString +
        (if (gated) "  AND2X2 g (.A(clock), .B(en), .Y(gclk));\n" else "  assign gclk = clock;\n") +
        (0 until n).map(i => s"  DFFPOSX1 r$i (.CLK(${if (gated) "gclk" else "clock"}), .D(${if (i == 0) "d" else s"s${i - 1}"}), .Q(s$i));\n").mkString +
        s"  assign q = s${n - 1};\nendmodule\n")
    val direct = sta(shift(gated = false), "sr", Seq(0.1)).clocks.head.internalMw
    val behind = sta(shift(gated = true), "sr", Seq(0.1)).clocks.head.internalMw
    assert(behind > 0.5 * direct && behind < 2 * direct, s"internal power behind the gate $behind mW, on the port $direct mW")
  }

  test("flip-flops behind a latch-and-AND clock gate open a fraction e of the cycles: e times the Liberty clock energy") {
    val dff = cell("DFFPOSX1")
    val n = 64
    val net = write(s"module greg(clock, en, d, q);\n  input clock;\n  input en;\n  input [${n - 1}:0] d;\n  output [${n - 1}:0] q;\n" +
      "  wire cn, h, g;\n  INVX1 i (.A(clock), .Y(cn));\n  LATCH l (.CLK(cn), .D(en), .Q(h));\n  AND2X2 a (.A(clock), .B(h), .Y(g));\n" +
      (0 until n).map(i => s"  DFFPOSX1 r$i (.CLK(g), .D(d[$i]), .Q(q[$i]));\n").mkString + "endmodule\n")
    val zero = Sta.Activity(0, 0.5)
    val pins = (0 until n).flatMap(i => Seq(s"r$i/D" -> zero, s"r$i/Q" -> zero)) ++ Seq("l/D" -> zero, "l/Q" -> zero)
    val ports = (0 until n).map(i => s"d[$i]" -> zero) :+ ("en" -> zero)
    val f = 0.5
    def at(e: Double): Sta.AtClock = Sta.run(Seq(net), "greg", tools().osu018Lib, Seq(f), net.getParent.resolve(s"sta-$e"), pins, ports,
      gated = Seq(Sta.GatedLevel((0 until n).map(i => s"r$i") :+ "a", e, Set("a")), Sta.GatedLevel(Seq("l"), 1.0)),
      stopPins = Seq("l/Q")).clocks.head
    val lo = dff.riseEnergy.min + dff.fallEnergy.min
    val hi = dff.riseEnergy.max + dff.fallEnergy.max
    val overhead = 0.02 // pJ per flip-flop and cycle: the inverter's and the latch's share, always clocked
    val (full, stopped) = (at(1.0), at(0.0))
    val perCycle = (r: Sta.AtClock) => r.dynamicMw / f / n
    info(f"per flip-flop and cycle: stopped ${perCycle(stopped)}%.4f pJ, open ${perCycle(full)}%.4f pJ; Liberty CLK energy $lo%.4f to $hi%.4f pJ")
    // Stopped, a flip-flop keeps its data pin's energy (the input ports' default activity) and
    // its share of the latch's: well below a clocked cycle's.
    assert(perCycle(stopped) < 0.5 * perCycle(full), s"stopped: ${perCycle(stopped)} pJ per flip-flop cycle")
    for (e <- Seq(0.0, 0.25, 0.75)) {
      val r = at(e)
      val pj = perCycle(r) - perCycle(stopped)
      assert(pj >= e * lo - 1e-9 && pj <= e * hi + overhead, s"duty $e: $pj pJ per flip-flop cycle outside [${e * lo}, ${e * hi} + $overhead]")
      // Linear in the duty between the stopped and the open figures; the open figure in every cycle kept beside.
      assert(math.abs(pj - e * (perCycle(full) - perCycle(stopped))) < 1e-6)
      assert(math.abs(r.ungatedDynamicMw.get - full.dynamicMw) < 1e-6)
    }
    assert(perCycle(full) - perCycle(stopped) >= lo && perCycle(full) - perCycle(stopped) <= hi + overhead)
  }

  test("a path from one module into another is timed whole: hierarchical and hand-flattened netlists need the same period") {
    val k = 12
    def invs(prefix: String, from: String, to: String): String =
      (0 until k).map { i =>
        val in = if (i == 0) from else s"${prefix}n$i"; val out = if (i == k - 1) to else s"${prefix}n${i + 1}"
        s"  INVX1 ${prefix}u$i (.A($in), .Y($out));\n"
      }.mkString
    def wires(prefix: String): String = (1 until k).map(i => s"  wire ${prefix}n$i;\n").mkString
    // drive: a flip-flop, then k inverters to its output; take: k inverters from its input into a flip-flop.
    // Every flip-flop sits behind a clock gate, so that both analyses give its clock pin the same transition.
    val drive = s"module drive(gclk, d, y);\n  input gclk;\n  input d;\n  output y;\n  wire q;\n${wires("")}" +
      s"  DFFPOSX1 r (.CLK(gclk), .D(d), .Q(q));\n${invs("", "q", "y")}endmodule\n"
    val take = s"module take(gclk, a, q);\n  input gclk;\n  input a;\n  output q;\n  wire x;\n${wires("")}" +
      s"${invs("", "a", "x")}  DFFPOSX1 r (.CLK(gclk), .D(x), .Q(q));\nendmodule\n"
    val hier = write(drive + take +
      "module top(clock, en, d, q);\n  input clock;\n  input en;\n  input d;\n  output q;\n  wire gclk;\n  wire m;\n" +
      "  AND2X2 g (.A(clock), .B(en), .Y(gclk));\n  drive a (.gclk(gclk), .d(d), .y(m));\n  take b (.gclk(gclk), .a(m), .q(q));\nendmodule\n")
    val flat = write("module top(clock, en, d, q);\n  input clock;\n  input en;\n  input d;\n  output q;\n  wire gclk;\n  wire m;\n  wire q0;\n  wire x;\n" +
      wires("a_") + wires("b_") + "  AND2X2 g (.A(clock), .B(en), .Y(gclk));\n  DFFPOSX1 ra (.CLK(gclk), .D(d), .Q(q0));\n" +
      invs("a_", "q0", "m") + invs("b_", "m", "x") + "  DFFPOSX1 rb (.CLK(gclk), .D(x), .Q(q));\nendmodule\n")
    val whole = Sta.timeWhole(Seq(hier), "top", tools().osu018Lib, hier.getParent.resolve("whole"))
    val reference = sta(flat, "top", Seq(0.1))
    assert(whole.instances == 2 * k + 3, s"${whole.instances} leaf cells")
    assert(math.abs(1 / whole.fmaxGHz - 1 / reference.fmaxGHz) < 2e-3,
      s"whole ${1 / whole.fmaxGHz} ns, flattened ${1 / reference.fmaxGHz} ns")
    assert(whole.worst.head.startPoint.startsWith("a/r/") && whole.worst.head.endPoint == "b/r/D", whole.worst.toString)
    assert(whole.worst.head.through == Seq("a", "b"), whole.worst.toString)
    assert(whole.worst.head.slackNs >= 0 && whole.worst.head.slackNs < 2e-3, whole.worst.toString)
    // Each module alone (inputs at the edge, outputs required at it) needs about half the crossing's period.
    val inv = cell("INVX1")
    for ((text, top) <- Seq(drive -> "drive", take -> "take")) {
      val alone = 1 / sta(write(text), top, Seq(0.1)).fmaxGHz
      assert(alone + (k - 2) * inv.delays.min < 1 / whole.fmaxGHz, s"$top alone needs $alone ns, the crossing ${1 / whole.fmaxGHz} ns")
    }
  }

  test("timed whole, a clock gate's enable latch gets half a period: the period found is the bisection's, not the first trial's period minus its slack") {
    // A flip-flop, k inverters, then the enable latch of a clock gate (transparent while the clock
    // is low, as a latch-based gate's is: it closes at the rising edge and opens at the falling
    // one, half a period in); the latch's output gates a second flip-flop's clock. A full-period
    // path of j inverters between the flip-flops is shorter than the latch path's period (2 d).
    def invs(prefix: String, from: String, to: String, k: Int): String = invChain(from, to, k, prefix)
    val net = write("module top(clock, d, q);\n  input clock;\n  input d;\n  output q;\n" +
      "  wire q0;\n  wire e;\n  wire en;\n  wire nclk;\n  wire gclk;\n  wire x;\n" +
      "  DFFPOSX1 r0 (.CLK(clock), .D(d), .Q(q0));\n" + invs("l", "q0", "e", 10) +
      "  INVX1 ci (.A(clock), .Y(nclk));\n  LATCH gl (.CLK(nclk), .D(e), .Q(en));\n  AND2X2 g (.A(clock), .B(en), .Y(gclk));\n" +
      invs("f", "q0", "x", 6) + "  DFFPOSX1 r1 (.CLK(gclk), .D(x), .Q(q));\nendmodule\n")
    val whole = Sta.timeWhole(Seq(net), "top", tools().osu018Lib, net.getParent.resolve("whole-latch"))
    val bisected = 1 / sta(net, "top", Seq(0.1)).fmaxGHz
    val (p0, s0) = whole.trials.head
    assert(p0 - s0 > 1.5 / whole.fmaxGHz, s"the first trial's guess ${p0 - s0} ns against ${1 / whole.fmaxGHz} ns: the latch path did not rule at 10 ns")
    assert(math.abs(1 / whole.fmaxGHz - bisected) < 2e-3, s"whole ${1 / whole.fmaxGHz} ns (trials ${whole.trials}), bisection $bisected ns")
    assert(whole.worst.head.endPoint == "gl/D" && whole.worst.head.slackNs >= 0 && whole.worst.head.slackNs < 2e-3, whole.worst.toString)
  }

  test("timed whole, a netlist OpenSTA cannot read is a one-line error naming the top and the log") {
    val net = write("module top(clock, a, q);\n  input clock;\n  input a;\n  output q;\n  INVX1 u (.A(a), .Y(q))\nendmodule\n")
    val e = intercept[mapm.MapmError](Sta.timeWhole(Seq(net), "top", tools().osu018Lib, net.getParent.resolve("whole-bad")))
    assert(e.getMessage.startsWith("OpenSTA failed timing top whole:") && !e.getMessage.contains("\n"), e.getMessage)
    assert(Files.isRegularFile(net.getParent.resolve("whole-bad").resolve("sta-whole.log")))
  }

  test("timed whole, a configuration input (io_cfg...) starts no path: it holds its value for a frame") {
    def invs(from: String, to: String, k: Int, p: String): String = invChain(from, to, k, p)
    val net = write("module top(clock, io_cfg_x, a, q, r);\n  input clock;\n  input io_cfg_x;\n  input a;\n  output q;\n  output r;\n" +
      "  wire x;\n  wire y;\n" + invs("io_cfg_x", "x", 30, "c") + invs("a", "y", 3, "d") +
      "  DFFPOSX1 rq (.CLK(clock), .D(x), .Q(q));\n  DFFPOSX1 rr (.CLK(clock), .D(y), .Q(r));\nendmodule\n")
    val whole = Sta.timeWhole(Seq(net), "top", tools().osu018Lib, net.getParent.resolve("whole"))
    val withCfg = 1 / sta(net, "top", Seq(0.1)).fmaxGHz
    assert(whole.worst.forall(p => !p.startPoint.startsWith("io_cfg")), whole.worst.toString)
    assert(1 / whole.fmaxGHz < withCfg / 3, s"whole ${1 / whole.fmaxGHz} ns, through the configuration input $withCfg ns")
  }
}

object StaSpec {
  /** This test's own reading of one cell of the Liberty text. */
  private final case class CellData(area: Double, leakageNw: Double, body: String) {
    private def values(group: String): Seq[Double] =
      (group + """\s*\([^)]*\)\s*\{[^}]*?values\s*\(([^)]*)\)""").r.findAllMatchIn(body).toSeq
        .flatMap(_.group(1).replaceAll("""[\\"\s]""", "").split(",").filter(_.nonEmpty).map(_.toDouble))
    def delays: Seq[Double] = values("cell_rise") ++ values("cell_fall")
    def riseEnergy: Seq[Double] = values("rise_power")
    def fallEnergy: Seq[Double] = values("fall_power")
    def pinCap(pin: String): Double =
      ("""pin\s*\(\s*""" + pin + """\s*\)\s*\{\s*[^}]*?\bcapacitance\s*:\s*([0-9.eE+-]+)""").r.findFirstMatchIn(body).get.group(1).toDouble
  }
}
