package mapm.arith

import chisel3._
import chisel3.util._
import mapm.util.StageClocks

/** Parallel to serial (3.4.5, 3.6): a triangular register array that delays bit `i` of a
  * `width`-bit word by `width - 1 - i` cycles, so that a word presented at cycle t reaches the
  * pipeline behind it most significant bit first: bit `width-1` at cycle t, bit `i` at cycle
  * t + (width-1-i). A new word may enter every cycle; the words overlap in the array.
  *
  * With `stallable`, an `en` input freezes every register while low (the array holds its
  * words); without it the array shifts every cycle.
  *
  * With `gated`, `clocks(k)` clocks the registers that load at the end of the k-th cycle after
  * the word's (k = 0 … width−2): the word's bits still in the array then.
  *
  * Latency: bit i is delayed by width-1-i cycles (the MSB passes straight through).
  * Throughput: one word per cycle. Registers: width*(width-1)/2 flip-flops.
  */
class P2S(width: Int, stallable: Boolean = false, gated: Boolean = false) extends Module {
  require(width >= 1, s"P2S width must be at least 1, got $width")
  require(!(stallable && gated), "P2S: a stallable array has no stage clocks")
  override def desiredName = s"P2S_w$width${if (stallable) "_en" else ""}${StageClocks.suffix(gated)}"

  val io = IO(new Bundle {
    /** The parallel word, sampled every cycle. */
    val in = Input(UInt(width.W))
    /** Bit i of the word that entered width-1-i cycles ago, for each i. */
    val out = Output(UInt(width.W))
    /** Shift enable (stallable arrays only): registers hold while it is low. */
    val en = if (stallable) Some(Input(Bool())) else None
    /** clocks(k): the clock of the registers loading k cycles after the word's (with `gated`). */
    val clocks = StageClocks.port(width - 1, gated)
  })

  private val enable = io.en.getOrElse(true.B)
  private val sc = new StageClocks(io.clocks)
  io.out := VecInit((0 until width).map(i =>
    if (gated) sc.shift(io.in(i), width - 1 - i, 0) else ShiftRegister(io.in(i), width - 1 - i, enable))).asUInt
}
