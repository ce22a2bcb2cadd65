package mapm.arith

import chisel3._
import chisel3.util._
import mapm.util.StageClocks

/** Pipelined radix-2 online multiplier (shader-chain.md §3.1, online-arithmetic.md §1):
  * P = x·y with x a signed-digit stream of `xLen` digits (converted on the fly into X/XM) and y
  * an n-bit binary operand, producing N = `digits` digits with |x·y − P| < 2^-N.
  * δ = 3, t = 2, residual W = n + 5 bits (I = 2, F = n + 3) in carry-save form; the [4:2] adder
  * is CSA(CSA(2WS, 2WC, A), B), the carry-in for x = −1 enters at VC bit 0, and the top field of
  * WS becomes v̂ − 4p (WC's top field 0).
  *
  * One registered stage per iteration: stage s (s = 1 … N+3) runs iteration j = s − 4. The
  * ports are skewed: in the cycle in which an operation occupies stage s, `x(s-1)` must carry
  * its digit x_s and `y(s-1)` its bit y_s. Digit p_i is computed in stage i+3 and appears on
  * `p(i-1)` from the next cycle (a register), i.e. i+3 cycles after the operation entered
  * stage 1. A new operation may enter every cycle; there is no stall.
  *
  * Registers hold only state that can still reach a digit: the residual's top bit (2·WS drops
  * it) and, in the last stages, low residual bits and the low bits of X and Y (a CSA moves
  * information up by at most one bit, so the state entering stage t influences the last
  * estimate only through its bits ≥ W − 7 − 3·(N+3 − t)). The dropped bits are zeros in the
  * next stage; the digits are those of the full-width recurrence.
  *
  * With `gated`, `clocks(s-1)` clocks the registers stage s loads (those of the state entering
  * stage s+1, and the digit it selects): the parent's [[mapm.util.StageGates]] gates it by the
  * valid bit of the operation in stage s.
  */
class OnlineMul(n: Int, digits: Int, xLen: Int, gated: Boolean = false) extends Module {
  require(n >= 2 && digits >= 1 && xLen >= 1 && xLen <= digits + 3, s"OnlineMul: n = $n, N = $digits, x length $xLen")
  override def desiredName = s"OnlineMul_n${n}_N${digits}_x$xLen${StageClocks.suffix(gated)}"

  val stages: Int = digits + 3
  private val w = n + 5

  val io = IO(new Bundle {
    /** x(s-1): digit x_s of the operation in stage s. */
    val x = Input(Vec(xLen, new SignedDigit))
    /** y(s-1): bit y_s of the operation in stage s. */
    val y = Input(Vec(n, Bool()))
    /** p(i-1): product digit p_i, registered (from stage i+3). */
    val p = Output(Vec(digits, new SignedDigit))
    /** clocks(s-1): the clock of stage s's registers (with `gated`). */
    val clocks = StageClocks.port(stages, gated)
  })
  private val sc = new StageClocks(io.clocks)

  /** Lowest residual bit of the state entering stage t that can reach a digit. */
  private def liveLow(t: Int): Int = math.max(0, w - 7 - 3 * (stages - t))
  /** Bits y_1 … y_k of Y held entering stage t: those that reach a digit (y_i matters in stage
    * t when i ≤ 3·(N+3 − t)) and are known (i < t). */
  private def yHeld(t: Int): Int = math.min(math.min(t - 1, n), 3 * (stages - t))
  /** Fraction bits of X held entering stage t ≤ n (X[j] has t − 1; bit i matters when
    * i ≤ 1 + 3·(N+3 − t)). Later digits still update the held bits through borrows. */
  private def xHeld(t: Int): Int = math.min(t - 1, 1 + 3 * (stages - t))
  /** Fraction bits of XM held entering stage t ≤ n: XM only updates X and itself, so all of X's
    * while stage t appends a digit, else those that X and XM keep after stage t. */
  private def xmHeld(t: Int): Int =
    if (t + 1 > n) 0 else if (xHeld(t + 1) == t) xHeld(t) else xHeld(t + 1)

  // State entering stage s: residual bits W−2 … 0 (live ones registered, zeros below), X/XM
  // (sign and xHeld(s) fraction bits, while s ≤ n) and Y = y_1 … y_yHeld(s) (while s ≤ xLen).
  var ws: UInt = 0.U((w - 1).W)
  var wc: UInt = 0.U((w - 1).W)
  var (xq, xqm) = OnTheFly.init
  var yBits: Option[UInt] = None

  /** Highest residual bit of the state entering stage t that can reach a digit: W−2 (2·WS drops
    * the top bit), one less per initialization stage before stage 4, as those select nothing
    * and their top bits reach only bits that later doublings drop. */
  private def liveHigh(t: Int): Int = w - 2 - math.max(0, 4 - t)

  /** Registers the live bits of a residual vector for stage t, zeros elsewhere (W−1 bits). */
  private def keepResidual(v: UInt, t: Int): UInt = CarrySave.keep(v, liveHigh(t), liveLow(t), w - 1)

  for (s <- 1 to stages) {
    val j = s - 4
    val a = if (s <= xLen) io.x(s - 1) else SignedDigit.zero
    val b = if (s <= n) io.y(s - 1) else false.B

    // Y[j+1] = y_1 … y_min(s,n), of which the bits that matter here: y_s joins while it does.
    val grows = s <= n && s <= 3 * (stages - s)
    val yNow = if (s > xLen) None else if (grows) Some(yBits.fold(b.asUInt)(Cat(_, b))) else yBits
    // A = b·X[j]·2^-3: X sign-extended, its fraction bit i at residual bit n − i.
    val multA =
      if (s <= n) Mux(b, Cat(Fill(w - n - 1, xq(xq.getWidth - 1)), xq, 0.U((n - xq.getWidth + 1).W)), 0.U(w.W))
      else 0.U(w.W)
    // B = a·Y[j+1]·2^-3 (y_i at residual bit n − i); for a = −1 the complement over all W bits,
    // plus a carry-in at VC bit 0.
    val yVec = yNow.fold(0.U(w.W))(y => (if (y.getWidth < n) Cat(y, 0.U((n - y.getWidth).W)) else y).pad(w))
    val multB = Mux(a.isPlus, yVec, Mux(a.isMinus, ~yVec, 0.U(w.W)))

    val (s1, c1) = CarrySave.csa(Cat(ws, 0.U(1.W)), Cat(wc, 0.U(1.W)), multA, w)
    val (vs, vc0) = CarrySave.csa(s1, c1, multB, w)
    val vc = vc0 | a.isMinus.asUInt

    // Estimate: the 4-bit sum of the top fields, in units of 1/4; SELM on its top 3 bits (the
    // last stage forms only those: its LSB matters there only through its carry).
    val est =
      if (s < stages) vs(w - 1, w - 4) + vc(w - 1, w - 4)
      else Cat(vs(w - 1, w - 3) + vc(w - 1, w - 3) + (vs(w - 4) & vc(w - 4)).asUInt, 0.U(1.W))
    val sel = if (j >= 0) MulSelect(est(3, 1)) else SignedDigit.zero
    if (j >= 0) io.p(j) := sc.reg(sel, s - 1)

    if (s < stages) sc.at(s - 1) {
      val top = est - Mux(sel.pos, 4.U(4.W), Mux(sel.neg, 12.U(4.W), 0.U(4.W)))
      ws = keepResidual(Cat(top, vs(w - 5, 0)), s + 1)
      wc = CarrySave.keep(vc, math.min(w - 5, liveHigh(s + 1)), liveLow(s + 1), w - 1) // WC's top field is 0
      if (s + 1 <= n) {
        val (nq, nqm) = OnTheFly.appendKeeping(xq, xqm, a, xHeld(s + 1), xmHeld(s + 1))
        xq = StageReg(nq); xqm = StageReg(nqm)
      }
      yBits =
        if (s + 1 > xLen || yHeld(s + 1) == 0) None
        else yNow.map(y => StageReg(y >> (y.getWidth - yHeld(s + 1))))
    }
  }
}

/** SELM by the top 3 bits v₋₁v₀.v₁ of the 4-bit estimate v̂ (units of 1/4): +1 for 001 … 011
  * (v̂ ≥ 1/2), −1 for 100 … 110 (v̂ ≤ −3/4), 0 for 000 and 111. */
object MulSelect {
  def apply(top3: UInt): SignedDigit =
    SignedDigit(!top3(2) && (top3(1) || top3(0)), top3(2) && !(top3(1) && top3(0)))
}
