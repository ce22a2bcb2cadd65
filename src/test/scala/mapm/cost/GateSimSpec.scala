package mapm.cost

import mapm.Slow
import java.nio.file.Files
import mapm.MapmError
import org.scalatest.funsuite.AnyFunSuite
import scala.util.Random

/** The gate-level simulator: yosys-synthesized designs against Scala arithmetic, random netlists
  * of every OSU cell against a plain reference simulation, exact toggle counts, refusals.
  */
@Slow
class GateSimSpec extends AnyFunSuite {
  private def lib: Liberty.Library = YosysSynth.library

  test("registered multiply-add out <= a*b + c: 64 lanes of different values against Scala") {
    val synth = YosysSynth(
      """module MulAdd(input clock, input [7:0] a, input [7:0] b, input [7:0] c, output reg [15:0] out);
        |  always @(posedge clock) out <= a * b + c;
        |endmodule
        |""".stripMargin, "MulAdd")
    val sim = new GateSim(synth.netlist, lib)
    val rnd = new Random(1)
    for (_ <- 0 until 30) {
      val in = Array.fill(64, 3)(rnd.nextInt(256).toLong)
      for (lane <- 0 until 64) {
        sim.pokeLong("a", lane, in(lane)(0))
        sim.poke("b", lane, BigInt(in(lane)(1)))
      }
      sim.poke("c", in.map(lane => BigInt(lane(2))).toSeq)
      sim.step()
      for (lane <- 0 until 64) {
        val expected = (in(lane)(0) * in(lane)(1) + in(lane)(2)) & 0xffff
        assert(sim.peekLong("out", lane) == expected, s"lane $lane: ${in(lane).mkString(" ")}")
        assert(sim.peek("out", lane) == BigInt(expected))
      }
    }
    assert(sim.cycles == 30)
  }

  test("4-bit counter with synchronous reset and enable, per-lane control") {
    val synth = YosysSynth(
      """module Counter(input clock, input reset, input en, output reg [3:0] count);
        |  always @(posedge clock) if (reset) count <= 4'd0; else if (en) count <= count + 4'd1;
        |endmodule
        |""".stripMargin, "Counter")
    val sim = new GateSim(synth.netlist, lib)
    val rnd = new Random(2)
    val model = Array.fill(64)(0)
    for (cycle <- 0 until 60) {
      for (lane <- 0 until 64) {
        val reset = cycle == 0 || rnd.nextInt(20) == 0
        val en = rnd.nextInt(4) != 0
        sim.pokeLong("reset", lane, if (reset) 1 else 0)
        sim.pokeLong("en", lane, if (en) 1 else 0)
        model(lane) = if (reset) 0 else if (en) (model(lane) + 1) & 15 else model(lane)
      }
      sim.step()
      for (lane <- 0 until 64) assert(sim.peekLong("count", lane) == model(lane), s"cycle $cycle lane $lane")
    }
  }

  test("FAX1/HAX1 ripple adder (two-output cells) and the JSON names are the Verilog names") {
    val synth = YosysSynth(
      """module Adder4(input clock, input [3:0] a, input [3:0] b, output reg [4:0] s);
        |  wire [3:0] c; wire [3:0] y;
        |  HAX1 h0(.A(a[0]), .B(b[0]), .YC(c[0]), .YS(y[0]));
        |  FAX1 f1(.A(a[1]), .B(b[1]), .C(c[0]), .YC(c[1]), .YS(y[1]));
        |  FAX1 f2(.A(a[2]), .B(b[2]), .C(c[1]), .YC(c[2]), .YS(y[2]));
        |  FAX1 f3(.A(a[3]), .B(b[3]), .C(c[2]), .YC(c[3]), .YS(y[3]));
        |  always @(posedge clock) s <= {c[3], y};
        |endmodule
        |""".stripMargin, "Adder4", structural = true)
    val netlist = synth.netlist
    assert(netlist.area(lib).counts == Map("HAX1" -> 1, "FAX1" -> 3, "DFFPOSX1" -> 5))
    val instance = """(?m)^\s+([A-Z][A-Z0-9]*)\s+(\S+)\s*\($""".r
    val verilogCells = instance.findAllMatchIn(new String(Files.readAllBytes(synth.verilog))).map(m => m.group(2) -> m.group(1)).toSet
    assert(verilogCells == netlist.cells.map(c => c.name -> c.cellType).toSet)
    val sim = new GateSim(netlist, lib)
    for (lane <- 0 until 64) { sim.pokeLong("a", lane, lane & 15); sim.pokeLong("b", lane, lane >> 2) }
    sim.step()
    for (lane <- 0 until 64) assert(sim.peekLong("s", lane) == (lane & 15) + (lane >> 2), s"lane $lane")
  }

  test("random netlists of every cell, shuffled, rising and falling edge flops: every net against the reference") {
    for (seed <- 1 to 3) {
      val rnd = new Random(seed)
      val g = RandomNetlist(cells = 600, flops = 60, inputs = 24, outputs = 8, Seq("DFFPOSX1", "DFFNEGX1", "DFFSR"), rnd)
      val sim = new GateSim(g.netlist, lib)
      val ref = new RandomNetlist.Reference(g)
      val inNets = g.netlist.port("in").get.nets
      for (cycle <- 0 until 25) {
        for (lane <- 0 until 64) {
          val v = rnd.nextLong() & 0xffffffL
          sim.pokeLong("in", lane, v)
          for ((net, k) <- inNets.zipWithIndex) ref.set(net, lane, ((v >> k) & 1) == 1)
        }
        ref.settle()
        for (net <- 2 until g.netlist.netCount)
          assert(sim.netLanes(net) == ref.lanes(net), s"seed $seed cycle $cycle net $net")
        sim.step()
        ref.step()
      }
    }
  }

  test("toggle and high counts on a known pattern, counter reset, clock, driver names") {
    val synth = YosysSynth(
      """module Toggle(input clock, input d, output reg q, output nq);
        |  always @(posedge clock) q <= d;
        |  assign nq = ~q;
        |endmodule
        |""".stripMargin, "Toggle")
    val netlist = synth.netlist
    val sim = new GateSim(netlist, lib, lanes = 2)
    def net(port: String): Int = netlist.port(port).get.nets.head
    // lane 0: d = 0, 1, 0, 1 ...; lane 1: d = 1 always. q follows d one cycle later, from 0.
    def cycle(k: Int): Unit = { sim.pokeLong("d", 0, k % 2); sim.pokeLong("d", 1, 1); sim.step() }
    (0 until 10).foreach(cycle)
    assert(sim.cycles == 10)
    // d samples: lane 0 0101010101 (9 toggles, 5 high), lane 1 all 1 (0 toggles, 10 high)
    assert(sim.toggles(net("d")) == 9 && sim.highCount(net("d")) == 15)
    // q samples: lane 0 0010101010 (8 toggles, 4 high), lane 1 0111111111 (1 toggle, 9 high)
    assert(sim.toggles(net("q")) == 9 && sim.highCount(net("q")) == 13)
    assert(sim.toggles(net("nq")) == 9 && sim.highCount(net("nq")) == 7)
    assert(sim.activity(net("q")) == 9.0 / 20 && sim.duty(net("q")) == 13.0 / 20)
    assert(sim.activity(net("clock")) == 2.0 && sim.duty(net("clock")) == 0.5)

    sim.resetActivity()
    assert(sim.cycles == 0 && sim.toggles(net("q")) == 0)
    (10 until 14).foreach(cycle)
    // q samples 1010 in lane 0 after a 0 (4 toggles, 2 high); lane 1 stays 1 (0 toggles, 4 high)
    assert(sim.cycles == 4 && sim.toggles(net("q")) == 4 && sim.highCount(net("q")) == 6)

    val flop = netlist.cells.find(_.cellType == "DFFPOSX1").get
    assert(flop.pins("Q") == net("q"))
    assert(sim.driverName(net("q")).contains(s"${flop.name}/Q"))
    assert(sim.driverName(net("d")).contains("d"))
    assert(sim.driverName(Netlist.Zero).isEmpty)
    val report = sim.activityReport.map(a => a.driver -> a).toMap
    assert(report(s"${flop.name}/Q").names.contains("q") && report(s"${flop.name}/Q").toggles == 4)
    assert(report("clock").activity == 2.0 && report("d").duty == 6.0 / 8)
  }

  test("clock gates (mapm.util.ClockGate, one behind another): flops load only when enabled, gate duty and activity") {
    val synth = YosysSynth(mapm.util.ClockGate.verilog +
      """module Gated(input clock, input en1, input en2, input [3:0] d, output reg [3:0] q0, output reg [3:0] q1, output reg [3:0] q2);
        |  wire c1, c2;
        |  ClockGate g1(.in(clock), .en(en1), .out(c1));
        |  ClockGate g2(.in(c1), .en(en2), .out(c2));
        |  always @(posedge clock) q0 <= d;
        |  always @(posedge c1) q1 <= d;
        |  always @(posedge c2) q2 <= d;
        |endmodule
        |""".stripMargin, "Gated")
    val netlist = synth.netlist
    assert(netlist.cells.count(_.cellType == "LATCH") == 2)
    val sim = new GateSim(netlist, lib)
    assert(sim.clockNetwork.gates.size == 2)
    val rnd = new Random(5)
    val model = Array.fill(3, 64)(0L)
    val enabled = Array.fill(2)(0L)
    val cycles = 200
    for (_ <- 0 until cycles) {
      val in = Array.fill(64)((rnd.nextInt(16).toLong, rnd.nextInt(3) != 0, rnd.nextBoolean()))
      for (lane <- 0 until 64) {
        val (d, e1, e2) = in(lane)
        sim.pokeLong("d", lane, d); sim.pokeLong("en1", lane, if (e1) 1 else 0); sim.pokeLong("en2", lane, if (e2) 1 else 0)
        model(0)(lane) = d
        if (e1) { model(1)(lane) = d; enabled(0) += 1 }
        if (e1 && e2) { model(2)(lane) = d; enabled(1) += 1 }
      }
      sim.step()
      for (lane <- 0 until 64; k <- 0 until 3) assert(sim.peekLong(s"q$k", lane) == model(k)(lane), s"q$k lane $lane")
    }
    // The gates in network order, parent first: g1's duty is en1's, g2's en1 and en2's.
    val Seq(g1, g2) = sim.clockNetwork.gates
    assert(g2.parent == g1.held && g1.parent == netlist.port("clock").get.nets.head)
    assert(sim.gateDuty(0) == enabled(0).toDouble / (cycles * 64) && sim.gateDuty(1) == enabled(1).toDouble / (cycles * 64))
    assert(sim.gateDuty(0) > 0.6 && sim.gateDuty(0) < 0.73 && sim.gateDuty(1) > 0.28 && sim.gateDuty(1) < 0.4)
    val q1Flop = netlist.cells.find(c => c.cellType == "DFFPOSX1" && c.pins("Q") == netlist.port("q1").get.nets.head).get
    val c1 = q1Flop.pins("CLK")
    assert(sim.clockNetwork.clockOf(c1) == g1.held)
    assert(sim.activity(c1) == 2 * sim.gateDuty(0) && sim.duty(c1) == sim.gateDuty(0) / 2)
  }

  test("refusals: combinational loop, latch, foreign clock, bad pokes") {
    def port(name: String, dir: Liberty.Direction, nets: Int*) = Netlist.Port(name, dir, nets.toIndexedSeq, nets.indices.map(i => s"$name[$i]"))
    val in = Liberty.Direction.Input
    val loop = Netlist("loop", IndexedSeq(port("a", in, 2)), IndexedSeq(
      Netlist.Instance("n1", "NAND2X1", Map("A" -> 2, "B" -> 4, "Y" -> 3)),
      Netlist.Instance("n0", "INVX1", Map("A" -> 2, "Y" -> 5)),
      Netlist.Instance("n2", "NAND2X1", Map("A" -> 2, "B" -> 3, "Y" -> 4))), IndexedSeq.empty, 6)
    assert(intercept[MapmError](new GateSim(loop, lib)).getMessage ==
      "gate simulation of loop: combinational loop through n1 (NAND2X1), n2 (NAND2X1)")
    val latch = Netlist("latch", IndexedSeq(port("a", in, 2), port("clock", in, 3)),
      IndexedSeq(Netlist.Instance("l", "LATCH", Map("CLK" -> 3, "D" -> 2, "Q" -> 4))), IndexedSeq.empty, 5)
    assert(intercept[MapmError](new GateSim(latch, lib)).getMessage == "gate simulation of latch: a latch on a clock is not " +
      "open exactly while its clock is low (l, LATCH); only flip-flop clock pins and clock gates (a latch open while the clock is low, ANDed with it) may read a clock")
    val loose = latch.copy(top = "loose", cells = IndexedSeq(Netlist.Instance("l", "LATCH", Map("CLK" -> 2, "D" -> 2, "Q" -> 4))))
    assert(intercept[MapmError](new GateSim(loose, lib)).getMessage == "gate simulation of loose: unsupported cell LATCH (latch)")
    val clockLogic = latch.copy(top = "logic", cells = IndexedSeq(Netlist.Instance("x", "XOR2X1", Map("A" -> 3, "B" -> 2, "Y" -> 4))))
    assert(intercept[MapmError](new GateSim(clockLogic, lib)).getMessage.startsWith("gate simulation of logic: a clock feeds logic (x, XOR2X1)"))
    val tristate = latch.copy(top = "tri", cells = IndexedSeq(Netlist.Instance("t", "TBUFX1", Map("A" -> 2, "EN" -> 2, "Y" -> 4))))
    assert(intercept[MapmError](new GateSim(tristate, lib)).getMessage == "gate simulation of tri: unsupported cell TBUFX1 (tristate output Y)")
    val dataClock = latch.copy(top = "data", cells = IndexedSeq(Netlist.Instance("f", "DFFPOSX1", Map("CLK" -> 3, "D" -> 3, "Q" -> 4))))
    assert(intercept[MapmError](new GateSim(dataClock, lib)).getMessage.startsWith("gate simulation of data: a clock reaches a flip-flop's data (f, DFFPOSX1)"))
    val gated = latch.copy(top = "gated", cells = IndexedSeq(Netlist.Instance("f", "DFFPOSX1", Map("CLK" -> 2, "D" -> 2, "Q" -> 4))))
    assert(intercept[MapmError](new GateSim(gated, lib)).getMessage ==
      "gate simulation of gated: flip-flop f is clocked by a[0], not by the clock port clock or a clock gate")
    val sim = new GateSim(gated.copy(cells = IndexedSeq.empty), lib)
    assert(intercept[MapmError](sim.pokeLong("clock", 0, 1)).getMessage ==
      "gate simulation of gated: no input port clock to poke (the clock is driven by step())")
    assert(intercept[MapmError](sim.pokeLong("a", 0, 2)).getMessage == "gate simulation: 2 does not fit the 1 bits of input a")
    assert(intercept[MapmError](sim.poke("b", 0, BigInt(0))).getMessage.startsWith("gate simulation of gated: no input port b to poke (inputs: a)"))
  }
}
