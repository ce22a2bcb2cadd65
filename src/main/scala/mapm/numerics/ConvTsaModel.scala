package mapm.numerics

import mapm.numerics.TsaModel.Outcome

/** The conventional TSA (`mapm.tsearch.ConvTSA`), bit for bit: r_L = RN(p - h) and r_R = RN(-p - h)
  * by [[SoftFloat]], then TC_L = r_L < s, or r_L = s and r_L lies above the exact p - h;
  * TC_R = r_R < -s, or r_R = -s and r_R lies above the exact -p - h. Invalid operands (negative non-zero,
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
      def neg(x: Long) = x ^ (1L << (fmt.width - 1))
      Outcome(below(fmt, p, h, s), below(fmt, neg(p), h, neg(s)), error = false)
    }

  /** a == b as values (neither a NaN here). */
  private def equal(fmt: FloatFormat, a: Long, b: Long): Boolean =
    !SoftFloat.lt(fmt, a, b) && !SoftFloat.lt(fmt, b, a)

  /** a - h < t exactly, decided from r = RN(a - h) as the hardware decides it. */
  private def below(fmt: FloatFormat, a: Long, h: Long, t: Long): Boolean = {
    val r = SoftFloat.sub(fmt, a, h)
    SoftFloat.lt(fmt, r, t) || (equal(fmt, r, t) && above(fmt, r, a, h))
  }

  /** Whether the rounded r lies above the exact a - h. */
  private def above(fmt: FloatFormat, r: Long, a: Long, h: Long): Boolean = {
    def exact(x: Long) = new java.math.BigDecimal(fmt.decode(x))
    if (fmt.isInf(r)) fmt.sign(r) == 0 else exact(r).compareTo(exact(a).subtract(exact(h))) > 0
  }
}
