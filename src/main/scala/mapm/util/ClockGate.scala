package mapm.util

import chisel3._
import chisel3.util.HasBlackBoxInline

/** An integrated clock gate: `out` follows `in` while `en` is high, and stays low while it is low.
  * `en` passes a latch that is transparent while the clock is low, so it may change anywhere in
  * the cycle after the rising edge without a glitch on `out` (the standard latch-and-AND cell).
  *
  * Latency: `en` seen in a cycle decides that cycle's rising edge at its end. Combinational
  * otherwise; no flip-flops. In Verilator, the flip-flops behind a gated clock are not evaluated
  * in the cycles it is off; in silicon they do not switch. */
class ClockGate extends BlackBox with HasBlackBoxInline {
  override def desiredName = "ClockGate"
  val io = IO(new Bundle {
    val in = Input(Clock())
    val en = Input(Bool())
    val out = Output(Clock())
  })
  setInline("ClockGate.sv", ClockGate.verilog)
}

object ClockGate {
  /** The gate's SystemVerilog module. */
  val verilog: String =
    """// Integrated clock gate: en latched while the clock is low, ANDed with the clock (mapm.util.ClockGate).
      |module ClockGate(
      |  input  in,
      |  input  en,
      |  output out
      |);
      |  reg en_low;
      |  always_latch begin
      |    if (!in) en_low = en;
      |  end
      |  assign out = in & en_low;
      |endmodule
      |""".stripMargin

  /** `clock` gated by `en` (see [[ClockGate]]). */
  def apply(clock: Clock, en: Bool): Clock = {
    val g = Module(new ClockGate)
    g.io.in := clock
    g.io.en := en
    g.io.out
  }
}
