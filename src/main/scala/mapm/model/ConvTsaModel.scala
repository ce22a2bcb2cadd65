package mapm.model

import mapm.model.TsaModel.Outcome

/** The conventional TSA (`mapm.tsearch.ConvTSA`), bit for bit: r_L = RN(p - h) and r_R = RN(p + h)
  * by [[SoftFloat]], then TC_L = r_L < s, or r_L = s and r_L lies above the exact p - h;
  * TC_R = s < r_R, or r_R = s and r_R lies below the exact p + h. Invalid operands (negative non-zero,
  * infinite or NaN) give error and both TC bits, as the online TSA does.
  *
  * The rule gives the exact decisions (the argument is in ConvTSA's header), so the outcome always
  * equals [[TsaModel.evaluate]]'s; the tests check exactly that. The direction of a rounding is
  * needed only when the rounded sum equals s, and there it is found with exact decimal arithmetic
  * (every value of every format up to binary64 is a double, and a BigDecimal holds a double exactly).
  */
object ConvTsaModel {
  def evaluate(fmt: FloatFormat, p: Long, h: Long, s: Long): Outcome =
    if (TsaModel.inputError(fmt, p) || TsaModel.inputError(fmt, h) || TsaModel.inputError(fmt, s))
      Outcome(tcl = true, tcr = true, error = true)
    else {
      val rl = SoftFloat.sub(fmt, p, h)
      val rr = SoftFloat.add(fmt, p, h)
      val tcl = SoftFloat.lt(fmt, rl, s) || (equal(fmt, rl, s) && direction(fmt, rl, p, h, -1) > 0)
      val tcr = SoftFloat.lt(fmt, s, rr) || (equal(fmt, rr, s) && direction(fmt, rr, p, h, 1) < 0)
      Outcome(tcl, tcr, error = false)
    }

  /** a == b as values (neither a NaN here). */
  private def equal(fmt: FloatFormat, a: Long, b: Long): Boolean =
    !SoftFloat.lt(fmt, a, b) && !SoftFloat.lt(fmt, b, a)

  /** The sign of r - (p + sign * h), exactly: where the rounded sum r lies against the exact one. */
  private def direction(fmt: FloatFormat, r: Long, p: Long, h: Long, sign: Int): Int = {
    def exact(x: Long) = new java.math.BigDecimal(fmt.decode(x))
    val sum = exact(p).add(if (sign < 0) exact(h).negate else exact(h))
    if (fmt.isInf(r)) (if (fmt.sign(r) == 0) 1 else -1) else exact(r).compareTo(sum)
  }
}
