package mapm.arith

import chisel3._
import chisel3.util._
import mapm.util.StageClocks

/** One conditional quasi-normalization step on a skewed quotient digit stream (shader-chain.md
  * §3.2): s = 0 when (q_1, q_2) is (+1,0), (+1,+1), (−1,0) or (−1,−1), else s = 1 and the
  * string becomes (2q_1 + q_2, q_3, …, q_N, 0), worth exactly 2Q. Exactly one step, never more.
  *
  * Timing: digit q_i must be on `q(i-1)` in cycle c+i (c is any base cycle, as the divider's
  * outputs are). q'_i is formed in cycle c+i+1, when q_(i+1) arrives, and appears on `out(i-1)`
  * from cycle c+i+2 (one register stage); s appears on `s` from cycle c+3. One operation per
  * cycle. Because s = 1 implies 2q_1 + q_2 = q_1 when q_1 ≠ 0, q'_1 is q_1 if q_1 ≠ 0, else q_2.
  *
  * With `gated`, `clocks(k)` clocks the registers that load at the end of cycle c+k+1 (k = 0 …
  * N): the digit q_(k+1) kept a cycle, and what is formed in that cycle.
  */
class QuasiNormalize(digits: Int, gated: Boolean = false) extends Module {
  require(digits >= 2, s"QuasiNormalize: N = $digits")
  override def desiredName = s"QuasiNormalize_N$digits${StageClocks.suffix(gated)}"

  val io = IO(new Bundle {
    val q = Input(Vec(digits, new SignedDigit))
    val out = Output(Vec(digits, new SignedDigit))
    val s = Output(Bool())
    /** clocks(k): the clock of the registers loading in cycle c+k+1 (with `gated`). */
    val clocks = StageClocks.port(digits + 1, gated)
  })
  private val sc = new StageClocks(io.clocks)

  // q_i one cycle later, beside q_(i+1): loaded in cycle c+i.
  val late = io.q.zipWithIndex.map { case (q, k) => sc.reg(q, k) }
  val (q1, q2) = (late(0), io.q(1))
  val step = q1.isZero || (q1.isPlus && q2.isMinus) || (q1.isMinus && q2.isPlus)

  // stepAt(i-1): s of the operation whose q'_i is formed now (cycle c+i+1); it follows the
  // operation along. q'_i is loaded in cycle c+i+1 too (q'_1 in c+2).
  val stepAt = (1 until digits).scanLeft(step)((prev, i) => sc.reg(prev, i))
  io.out(0) := sc.reg(Mux(q1.isZero, q2, q1), 1)
  for (i <- 2 to digits) {
    val next = if (i < digits) io.q(i) else SignedDigit.zero
    io.out(i - 1) := sc.reg(Mux(stepAt(i - 1), next, late(i - 1)), i)
  }
  io.s := stepAt(1)
}
