package mapm.arith

import chisel3._
import chisel3.util._
import mapm.util.StageClocks

/** Pipelined radix-2 online divider (online-arithmetic.md §2): Q = x'/d with the dividend x' a
  * signed-digit stream of `xLen` digits (|x'| < d) and the divisor d an n-bit binary operand
  * (d_1 = 1), producing N = `digits` quotient digits with |x'/d − Q| < 2^-N and converting Q
  * on the fly (Q/QM) for the multiple T = (x − e·Q)·2^-4. The bound holds for the dividends
  * the chain gives it (x'_1 = 0, so |x'| < 1/2 ≤ d; all of them tested at n = 8); right at the
  * edge of |x'| < d the residual can leave its two integer bits (at n = 8, 18 of the 2,179,126
  * nine-digit dividends with |x'| < d, all within 5·2^-9 of d: docs/soa.md).
  * δ = 4, t = 3, residual W = n + 2 bits (I = 2, F = n) in carry-save form; −D is ¬D with a
  * carry-in at WC bit 0; the second CSA is present in every stage.
  *
  * One registered stage per iteration: stage s (s = 1 … N+4) runs iteration j = s − 5. Ports are
  * skewed: while an operation occupies stage s, `x(s-1)` carries its digit x'_s and `d(s-1)` its
  * bit d_s. Digit q_i is computed in stage i+4 and appears on `q(i-1)` from the next cycle.
  * A new operation may enter every cycle; there is no stall.
  *
  * Registers hold only state that can still reach a digit: the residual's top bit (2·WS drops
  * it) and, in the last stages, low residual bits and the low bits of QM and D (the state
  * entering stage t influences the last estimate only through its bits ≥ W − 7 − 3·(N+4 − t)).
  * The dropped bits are zeros in the next stage; the digits are those of the full-width
  * recurrence.
  *
  * With `gated`, `clocks(s-1)` clocks the registers stage s loads, as in [[OnlineMul]].
  */
class OnlineDiv(n: Int, digits: Int, xLen: Int, gated: Boolean = false) extends Module {
  require(n >= 4 && digits >= 1 && xLen >= 1 && xLen <= digits + 4, s"OnlineDiv: n = $n, N = $digits, x length $xLen")
  override def desiredName = s"OnlineDiv_n${n}_N${digits}_x$xLen${StageClocks.suffix(gated)}"

  val stages: Int = digits + 4
  private val w = n + 2

  val io = IO(new Bundle {
    /** x(s-1): dividend digit x'_s of the operation in stage s. */
    val x = Input(Vec(xLen, new SignedDigit))
    /** d(s-1): divisor bit d_s of the operation in stage s. */
    val d = Input(Vec(n, Bool()))
    /** q(i-1): quotient digit q_i, registered (from stage i+4). */
    val q = Output(Vec(digits, new SignedDigit))
    /** clocks(s-1): the clock of stage s's registers (with `gated`). */
    val clocks = StageClocks.port(stages, gated)
  })
  private val sc = new StageClocks(io.clocks)

  /** Lowest residual bit of the state entering stage t that can reach a digit. */
  private def liveLow(t: Int): Int = math.max(0, w - 7 - 3 * (stages - t))
  /** Bits d_1 … d_k of D held entering stage t: known (i < t) and reaching a digit (d_i matters
    * in stage t < N+4 when i ≤ 3 + 3·(N+4 − t); the last stage's second CSA is dead). */
  private def dHeld(t: Int): Int = if (t >= stages) 0 else math.min(math.min(t - 1, n), 3 + 3 * (stages - t))
  /** Fraction bits of QM held entering stage t ≤ n (Q[j] has t − 5; bit i matters when
    * i ≤ 3·(N+4 − t)). Later digits still update the held bits through borrows. */
  private def qHeld(t: Int): Int = math.max(0, math.min(t - 5, 3 * (stages - t)))
  /** Fraction bits of Q held entering stage t ≤ n: Q only updates Q and QM (T reads QM), so all
    * of QM's while stage t appends a digit, else those that Q and QM keep after stage t. */
  private def qOnlyHeld(t: Int): Int =
    if (t + 1 > n) 0 else if (qHeld(t + 1) == t - 4) qHeld(t) else qHeld(t + 1)

  // State entering stage s: residual bits W−2 … 0 (live ones registered, zeros below), D, and
  // while a later stage may still see e = 1 (s ≤ n), Q/QM with qHeld(s) fraction bits.
  var ws: UInt = 0.U((w - 1).W)
  var wc: UInt = 0.U((w - 1).W)
  var dBits: Option[UInt] = None
  var (q, qm) = OnTheFly.init

  /** Highest residual bit of the state entering stage t that can reach a digit: W−2 (2·WS drops
    * the top bit), one less per initialization stage before stage 5, as those select nothing
    * and their top bits reach only bits that later doublings drop. */
  private def liveHigh(t: Int): Int = w - 2 - math.max(0, 5 - t)

  /** Registers the live bits of a residual vector for stage t, zeros elsewhere (W−1 bits). */
  private def keepResidual(v: UInt, t: Int): UInt = CarrySave.keep(v, liveHigh(t), liveLow(t), w - 1)

  for (s <- 1 to stages) {
    val j = s - 5
    val x = if (s <= xLen) io.x(s - 1) else SignedDigit.zero
    val e = if (s <= n) io.d(s - 1) else false.B

    // T = (x − e·Q[j])·2^-4 as one exact vector: −Q is ¬QM over its sign and j fraction bits,
    // so the integer part at weight 2^-4 is x − e·(1 − sign(QM)) ∈ {−2 … 1}, sign-extended,
    // and the fraction part (bit i at weight 2^-(4+i)) is e ? ¬QM : 0.
    val xv = Mux(x.isPlus, 1.S(3.W), Mux(x.isMinus, -1.S(3.W), 0.S(3.W)))
    val intPart = (xv - Mux(e && !qm(qm.getWidth - 1), 1.S(3.W), 0.S(3.W))).pad(6).asUInt
    val f = qm.getWidth - 1
    val multT =
      if (s <= n && f > 0) Cat(intPart, Mux(e, ~qm(f - 1, 0), 0.U(f.W)), 0.U((n - 4 - f).W))
      else Cat(intPart, 0.U((n - 4).W))

    val (vs, vc) = CarrySave.csa(Cat(ws, 0.U(1.W)), Cat(wc, 0.U(1.W)), multT, w)

    // Estimate: the top 4 bits of the 5-bit sum of the top fields (units of 1/4; the sum's
    // LSB only matters through its carry); SELD on them.
    val est = vs(w - 1, w - 4) + vc(w - 1, w - 4) + (vs(w - 5) & vc(w - 5)).asUInt
    val sel = if (j >= 0) DivSelect(est) else SignedDigit.zero
    if (j >= 0) io.q(j) := sc.reg(sel, s - 1)

    if (s < stages) sc.at(s - 1) {
      // D[j+1] with d_i at residual bit n − i; the second CSA adds −q·D[j+1] (q = +1: ¬D and a
      // carry-in at WC bit 0).
      val grows = s <= n && s <= 3 + 3 * (stages - s)
      val dNow = if (grows) dBits.fold(e.asUInt)(Cat(_, e)) else dBits.get
      val dVec = (if (dNow.getWidth < n) Cat(dNow, 0.U((n - dNow.getWidth).W)) else dNow).pad(w)
      val multY = Mux(sel.isPlus, ~dVec, Mux(sel.isMinus, dVec, 0.U(w.W)))
      val (ns, nc) = CarrySave.csa(vs, vc, multY, w)
      ws = keepResidual(ns, s + 1)
      wc = keepResidual(nc | sel.isPlus.asUInt, s + 1)
      dBits = if (dHeld(s + 1) == 0) None else Some(StageReg(dNow >> (dNow.getWidth - dHeld(s + 1))))
      if (j >= 0 && s + 1 <= n) {
        val (nq, nqm) = OnTheFly.appendKeeping(q, qm, sel, qOnlyHeld(s + 1), qHeld(s + 1))
        q = StageReg(nq); qm = StageReg(nqm)
      }
    }
  }
}

/** SELD by the top 4 bits of the 5-bit estimate v̂ (units of 1/8): 0000 → 0, 0001 … 0111 → +1,
  * 1000 … 1110 → −1, 1111 → 0 (+1 for v̂ ≥ 1/4, −1 for v̂ ≤ −3/8). */
object DivSelect {
  def apply(top4: UInt): SignedDigit = {
    val t = top4(2, 0)
    SignedDigit(!top4(3) && t =/= 0.U, top4(3) && t =/= 7.U)
  }
}
