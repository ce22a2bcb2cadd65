package mapm.model

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

  /** Selection of the multiplier (SELM) on the 4-bit estimate in units of 1/4:
    * +1 if v̂ ≥ 1/2, −1 if v̂ ≤ −3/4, else 0. */
  @inline def selm(est: Int): Int = if (est >= 2) 1 else if (est <= -3) -1 else 0

  /** Selection of the divider (SELD) on the 5-bit estimate in units of 1/8:
    * +1 if v̂ ≥ 1/4, −1 if v̂ ≤ −3/8, else 0. */
  @inline def seld(est: Int): Int = if (est >= 2) 1 else if (est <= -3) -1 else 0

  /** Online multiplier, δ = 3, t = 2: x (signed digits, any length, missing digits 0) times the
    * n-bit binary operand y (bits y_1 … y_n held as bit n−1 … 0 of `y`). Returns the N = `digits`
    * product digits p_1 … p_N, with |x·y − P| < 2^-N.
    *
    * Iteration j = −3 … N−1 consumes a = x_(j+4), b = y_(j+4); the multiple terms are
    * A = b·X[j]·2^-3 (X converted on the fly, sign-extended) and B = a·Y[j+1]·2^-3 (a = −1:
    * the complement of Y over all W bits with a carry-in at VC bit 0); the [4:2] adder is
    * CSA(CSA(2WS, 2WC, A), B) in exactly that order. */
  def mul(x: DigitString, y: Long, n: Int, digits: Int, obs: Observer = null): DigitString = {
    require(n >= 2 && n <= 53 && digits >= 1 && digits <= DigitString.MaxLength, s"online multiplier: n = $n, N = $digits")
    val w = mulWidth(n)
    val mask = (1L << w) - 1
    val top = w - 4
    val low = (1L << top) - 1
    val xp = x.pos; val xn = x.neg; val xl = x.length
    var ws = 0L; var wc = 0L
    var xv = 0L // X[j] in units of 2^-n (two's complement through the Long's sign)
    var yv = 0L // Y[j+1] in units of 2^-n
    var outP = 0L; var outN = 0L
    var j = -3
    while (j < digits) {
      val idx = j + 4
      var a = 0
      if (idx <= xl) {
        val sh = xl - idx
        a = (((xp >>> sh) & 1L) - ((xn >>> sh) & 1L)).toInt
      }
      var ma = 0L
      if (idx <= n && ((y >>> (n - idx)) & 1L) != 0L) {
        yv |= 1L << (n - idx)
        ma = xv & mask
      }
      val mb = if (a > 0) yv else if (a < 0) ~yv & mask else 0L
      val s0 = (ws << 1) & mask
      val c0 = (wc << 1) & mask
      val s1 = s0 ^ c0 ^ ma
      val c1 = (((s0 & c0) | (s0 & ma) | (c0 & ma)) << 1) & mask
      val vs = s1 ^ c1 ^ mb
      val vc = ((((s1 & c1) | (s1 & mb) | (c1 & mb)) << 1) & mask) | (if (a < 0) 1L else 0L)
      val e4 = (((vs >>> top) + (vc >>> top)) & 15L).toInt
      val est = if (e4 >= 8) e4 - 16 else e4
      val p = if (j < 0) 0 else selm(est)
      ws = (vs & low) | (((est - 4 * p) & 15L) << top)
      wc = vc & low
      if (p > 0) outP |= 1L << (digits - 1 - j)
      else if (p < 0) outN |= 1L << (digits - 1 - j)
      if (a != 0 && idx <= n) xv += a.toLong << (n - idx)
      if (obs != null) obs.step(j, ws, wc, est, p)
      j += 1
    }
    DigitString(outP, outN, digits)
  }

  /** Online divider, δ = 4, t = 3: dividend x' (signed digits, any length, |x'| < d) over the
    * n-bit divisor d (d_1 = 1, bits held as bit n−1 … 0 of `d`). Returns the N = `digits`
    * quotient digits q_1 … q_N, with |x'/d − Q| < 2^-N.
    *
    * Iteration j = −4 … N−1 consumes x = x'_(j+5), e = d_(j+5); T is the exact vector
    * (x − e·Q[j])·2^-4, (VS, VC) = CSA(2WS, 2WC, T), and the second CSA subtracts q·D[j+1]
    * (q = +1: the complement of D with a carry-in at WC bit 0), in every stage. */
  def div(x: DigitString, d: Long, n: Int, digits: Int, obs: Observer = null): DigitString = {
    require(n >= 4 && n <= 53 && digits >= 1 && digits <= DigitString.MaxLength, s"online divider: n = $n, N = $digits")
    val w = divWidth(n)
    val mask = (1L << w) - 1
    val top = w - 5
    val xp = x.pos; val xn = x.neg; val xl = x.length
    var ws = 0L; var wc = 0L
    var dv = 0L // D[j+1] in units of 2^-n
    var qv = 0L // Q[j] in units of 2^-j (on-the-fly conversion keeps exactly this value)
    var outP = 0L; var outN = 0L
    var j = -4
    while (j < digits) {
      val idx = j + 5
      var xd = 0L
      if (idx <= xl) {
        val sh = xl - idx
        xd = ((xp >>> sh) & 1L) - ((xn >>> sh) & 1L)
      }
      val e = idx <= n && ((d >>> (n - idx)) & 1L) != 0L
      // (x − e·Q[j])·2^-4 in units of 2^-n; e = 1 only for j ≤ n − 5, so the shift is ≥ 1.
      val t = ((xd << (n - 4)) - (if (e) qv << (n - 4 - j) else 0L)) & mask
      val s0 = (ws << 1) & mask
      val c0 = (wc << 1) & mask
      val vs = s0 ^ c0 ^ t
      val vc = ((s0 & c0) | (s0 & t) | (c0 & t)) << 1 & mask
      val e5 = (((vs >>> top) + (vc >>> top)) & 31L).toInt
      val est = if (e5 >= 16) e5 - 32 else e5
      val q = if (j < 0) 0 else seld(est)
      if (e) dv |= 1L << (n - idx)
      val yv = if (q > 0) ~dv & mask else if (q < 0) dv else 0L
      ws = vs ^ vc ^ yv
      wc = ((((vs & vc) | (vs & yv) | (vc & yv)) << 1) & mask) | (if (q > 0) 1L else 0L)
      if (j >= 0) {
        qv = 2 * qv + q
        if (q > 0) outP |= 1L << (digits - 1 - j)
        else if (q < 0) outN |= 1L << (digits - 1 - j)
      }
      if (obs != null) obs.step(j, ws, wc, est, q)
      j += 1
    }
    DigitString(outP, outN, digits)
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
