package mapm.numerics

/** Bit-accurate model of the radix-2 online multiplier and divider of the shader chain
  * (../shared/design/online-arithmetic.md §0–§3 and shader-chain.md §3.1): the same carry-save
  * residual vectors, truncated estimates, selection functions and on-the-fly conversion as the
  * hardware in `mapm.shader`, iteration by iteration, so that both emit identical digit strings.
  *
  * Residual words are W-bit two's-complement vectors held in the low W bits of a Long (W ≤ 58
  * for n ≤ 53). All arithmetic is modulo 2^W, exactly as in the hardware.
  */
object OnlineArith {

  /** Receives the state after every iteration j (−δ … N−1): the new carry-save residual
    * (ws, wc), the estimate v̂ in units of 2^-t and the selected digit (0 for j < 0). For tests
    * that check the residual invariants; pass null (the default) for speed. */
  trait Observer {
    def step(j: Int, ws: Long, wc: Long, estimate: Int, digit: Int): Unit
  }

  /** Residual width of the multiplier: I = 2 integer bits, F = n + 3 fraction bits. */
  def mulWidth(n: Int): Int = n + 5
  /** Residual width of the divider: I = 2 integer bits, F = n fraction bits. */
  def divWidth(n: Int): Int = n + 2

  // Implementation notes (both units). The loops are branch-free for speed: operand digits and
  // bits are shifted out of the top of left-aligned Longs, a digit's weight is a mask that
  // halves each iteration (and becomes 0 below 2^-n), and the selection functions are bit
  // tables indexed by the estimate (all-zero tables during the initialization iterations). Residual words may carry garbage above bit W−1 between the
  // steps that mask them: a CSA and a left shift never move information downward, and the
  // estimate keeps only the low I+t bits of its sum, so those bits never reach a result.

  /** SELM as bit tables over the 4-bit estimate: +1 for 0010…0111, −1 for 1000…1101. */
  private final val SelmPos = 0x00FC
  private final val SelmNeg = 0x3F00
  /** The multiplier's new top field (v̂ − 4p) mod 16 by estimate, one nibble per value; and
    * the identity table, for the initialization iterations where p = 0. */
  private final val SelmTop = 0xFE10FEDC3210FE10L
  private final val Identity4 = 0xFEDCBA9876543210L
  /** SELD as bit tables over the 5-bit estimate: +1 for 00010…01111, −1 for 10000…11101. */
  private final val SeldPos = 0x0000FFFC
  private final val SeldNeg = 0x3FFF0000

  /** Online multiplier, δ = 3, t = 2: x (signed digits, any length, missing digits 0) times the
    * n-bit binary operand y (bits y_1 … y_n held as bit n−1 … 0 of `y`). Returns the N = `digits`
    * product digits p_1 … p_N, with |x·y − P| < 2^-N.
    *
    * Iteration j = −3 … N−1 consumes a = x_(j+4), b = y_(j+4); the multiple terms are
    * A = b·X[j]·2^-3 (X converted on the fly, sign-extended) and B = a·Y[j+1]·2^-3 (a = −1:
    * the complement of Y over all W bits with a carry-in at VC bit 0); the [4:2] adder is
    * CSA(CSA(2WS, 2WC, A), B) in exactly that order; the top field of WS becomes v̂ − 4p and
    * that of WC zero. */
  def mul(x: DigitString, y: Long, n: Int, digits: Int, obs: Observer = null): DigitString = {
    require(n >= 2 && n <= 53 && digits >= 1 && digits <= DigitString.MaxLength, s"online multiplier: n = $n, N = $digits")
    val w = mulWidth(n)
    val top = w - 4
    val low = (1L << top) - 1
    val xl = x.length
    var xp = if (xl == 0) 0L else x.pos << (64 - xl) // x_(j+4) is the top bit
    var xn = if (xl == 0) 0L else x.neg << (64 - xl)
    var yb = y << (64 - n)                             // y_(j+4) is the top bit
    var wgt = 1L << (n - 1)                            // weight 2^-(j+4) in units of 2^-n
    var ws = 0L; var wc = 0L
    var xv = 0L // X[j] in units of 2^-n, two's complement (on-the-fly conversion keeps this value)
    var yv = 0L // Y[j+1] in units of 2^-n
    var outP = 0L; var outN = 0L
    var tSel = 0; var tTop = Identity4 // no selection while j < 0; then SELM (−1 table above bit 16)
    var j = -3
    while (j < digits) {
      if (j == 0) { tSel = SelmPos | (SelmNeg << 16); tTop = SelmTop }
      val ap = xp >>> 63; val an = xn >>> 63
      xp <<= 1; xn <<= 1
      val b = yb >>> 63
      yb <<= 1
      yv |= wgt & -b
      val ma = xv & -b
      val mb = (yv & -ap) | (~yv & -an)
      val s0 = ws << 1; val c0 = wc << 1
      val u = s0 ^ c0
      val s1 = u ^ ma
      val c1 = ((s0 & c0) | (u & ma)) << 1
      val u1 = s1 ^ c1
      val vs = u1 ^ mb
      val vc = (((s1 & c1) | (u1 & mb)) << 1) | an
      val e4 = (((vs >>> top) + (vc >>> top)) & 15L).toInt
      val pp = (tSel >>> e4) & 1
      val pn = (tSel >>> (e4 + 16)) & 1
      ws = (vs & low) | (((tTop >>> (e4 << 2)) & 15L) << top)
      wc = vc & low
      xv += (wgt & -ap) - (wgt & -an)
      wgt >>>= 1
      outP = (outP << 1) | pp; outN = (outN << 1) | pn
      if (obs != null) obs.step(j, ws, wc, (e4 << 28) >> 28, pp - pn)
      j += 1
    }
    val m = (1L << digits) - 1
    DigitString(outP & m, outN & m, digits)
  }

  /** Online divider, δ = 4, t = 3: dividend x' (signed digits, any length, |x'| < d) over the
    * n-bit divisor d (d_1 = 1, bits held as bit n−1 … 0 of `d`). Returns the N = `digits`
    * quotient digits q_1 … q_N, with |x'/d − Q| < 2^-N for the chain's dividends (x'_1 = 0);
    * a dividend right at the edge of |x'| < d can overflow the residual (at n = 8, 18 nine-digit
    * ones, all within 5·2^-9 of d: docs/soa.md), as in the hardware.
    *
    * Iteration j = −4 … N−1 consumes x = x'_(j+5), e = d_(j+5); T is the exact vector
    * (x − e·Q[j])·2^-4, (VS, VC) = CSA(2WS, 2WC, T), and the second CSA subtracts q·D[j+1]
    * (q = +1: the complement of D with a carry-in at WC bit 0), in every stage. */
  def div(x: DigitString, d: Long, n: Int, digits: Int, obs: Observer = null): DigitString = {
    require(n >= 4 && n <= 53 && digits >= 1 && digits <= DigitString.MaxLength, s"online divider: n = $n, N = $digits")
    val w = divWidth(n)
    val mask = (1L << w) - 1
    val top = w - 5
    val xl = x.length
    var xp = if (xl == 0) 0L else x.pos << (64 - xl) // x'_(j+5) is the top bit
    var xn = if (xl == 0) 0L else x.neg << (64 - xl)
    var db = d << (64 - n)                             // d_(j+5) is the top bit
    var wgt = 1L << (n - 1)                            // weight 2^-(j+5) in units of 2^-n
    var wq = 1L << (n - 1)                             // weight 2^-(j+1)·2^-4 in units of 2^-n, from j = 0
    var ws = 0L; var wc = 0L
    var dv = 0L // D[j+1] in units of 2^-n
    var qt = 0L // Q[j]·2^-4 in units of 2^-n (exact while it matters: e = 0 once j > n − 5)
    var outP = 0L; var outN = 0L
    var tPos = 0L // no selection while j < 0; then SELD's +1 table, its −1 table above bit 32
    var j = -4
    while (j < digits) {
      if (j == 0) tPos = SeldPos | (SeldNeg.toLong << 32)
      val xp1 = xp >>> 63; val xn1 = xn >>> 63
      xp <<= 1; xn <<= 1
      val e = db >>> 63
      db <<= 1
      val t = ((xp1 - xn1) << (n - 4)) - (qt & -e)
      val s0 = ws << 1; val c0 = wc << 1
      val u = s0 ^ c0
      val vs = u ^ t
      val vc = ((s0 & c0) | (u & t)) << 1
      val e5 = (((vs >>> top) + (vc >>> top)) & 31L).toInt
      val qp = (tPos >>> e5) & 1L
      val qn = (tPos >>> (e5 + 32)) & 1L
      dv |= wgt & -e
      wgt >>>= 1
      val yv = (~dv & -qp) | (dv & -qn)
      val u2 = vs ^ vc
      ws = u2 ^ yv
      wc = (((vs & vc) | (u2 & yv)) << 1) | qp
      qt += (wq & -qp) - (wq & -qn)
      wq >>>= 1
      outP = (outP << 1) | qp; outN = (outN << 1) | qn
      if (obs != null) obs.step(j, ws & mask, wc & mask, (e5 << 27) >> 27, (qp - qn).toInt)
      j += 1
    }
    val m = (1L << digits) - 1
    DigitString(outP & m, outN & m, digits)
  }

  /** The quasi-normalization step s of a quotient (shader-chain.md §3.2): 0 when the first two
    * digits are (+1,0), (+1,+1), (−1,0) or (−1,−1), else 1. */
  def qnStep(q: DigitString): Int = {
    val q1 = q.digit(1); val q2 = q.digit(2)
    if (q1 != 0 && q2 != -q1) 0 else 1
  }

  /** Applies one quasi-normalization step: s = 0 leaves q as it is; s = 1 gives
    * (2q_1 + q_2, q_3, …, q_N), worth exactly 2q and one digit shorter. */
  def qnApply(q: DigitString, s: Int): DigitString =
    if (s == 0 || q.length < 2) q
    else {
      val l = q.length
      val lead = 2 * q.digit(1) + q.digit(2) // in {−1, 0, +1} whenever the step is taken
      val rest = (1L << (l - 2)) - 1
      DigitString(
        (q.pos & rest) | (if (lead > 0) 1L << (l - 2) else 0L),
        (q.neg & rest) | (if (lead < 0) 1L << (l - 2) else 0L),
        l - 1)
    }
}
