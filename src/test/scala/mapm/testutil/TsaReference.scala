package mapm.testutil

import mapm.numerics.FloatFormat

/** Independent references and input generators for the TSA tests.
  *
  * The reference decides p - h < s and p + h > s on the exact values, as integers: a normal
  * value with biased exponent e and significand m (hidden bit included) is m * 2^(e-1) in units
  * of 2^-(bias + manWidth - 1), which holds every finite value of the format exactly. */
object TsaReference {
  /** The exact value of a non-negative finite pattern, in units of 2^-(bias + manWidth - 1). */
  def value(fmt: FloatFormat, bits: Long): BigInt =
    if (fmt.expField(bits) == 0) BigInt(0)
    else BigInt((1L << fmt.manWidth) | fmt.manField(bits)) << (fmt.expField(bits) - 1)

  /** One unit in the last place at biased exponent e, in the same units (e = 0 counts as 1). */
  def ulp(e: Int): BigInt = BigInt(1) << (math.max(e, 1) - 1)

  /** Exact TC_L = (p - h < s). */
  def tcl(fmt: FloatFormat, p: Long, h: Long, s: Long): Boolean =
    value(fmt, p) - value(fmt, h) < value(fmt, s)

  /** Exact TC_R = (p + h > s). */
  def tcr(fmt: FloatFormat, p: Long, h: Long, s: Long): Boolean =
    value(fmt, p) + value(fmt, h) > value(fmt, s)

  /** Whether a pattern is an invalid TSA input, written from the rule (negative non-zero value,
    * infinity, NaN), not from the model. */
  def invalid(fmt: FloatFormat, bits: Long): Boolean = {
    val e = (bits >>> fmt.manWidth) & ((1L << fmt.expWidth) - 1)
    val negative = (bits >>> (fmt.width - 1)) == 1L
    e == (1L << fmt.expWidth) - 1 || (negative && e != 0)
  }

  /** Every non-negative finite pattern of `fmt` (exponent field 0 with any mantissa included). */
  def allValid(fmt: FloatFormat): IndexedSeq[Long] =
    for (e <- 0 until fmt.expMax; m <- 0L to fmt.manMask) yield fmt.pack(0, e, m)

  /** Seeded random (p, h, s) triples of non-negative finite patterns, weighted toward the hard
    * cases: equal exponents, s within a few ulp of p - h or p + h, exact equality (p - h = s or
    * p + h = s on the exact values), zeros (canonical and not), huge exponent gaps next to a tie,
    * and exponents at both ends of the range. */
  final class HardCases(fmt: FloatFormat, seed: Long) {
    private val rnd = new scala.util.Random(seed)
    private def mant(): Long = rnd.nextLong() & fmt.manMask
    private def withExp(e: Int): Long = fmt.pack(0, e, mant())
    private def anyExp(): Int = 1 + rnd.nextInt(fmt.expMax - 1)
    private def uniform(): Long = withExp(rnd.nextInt(fmt.expMax))
    /** A pattern a few steps (ulp) from the format's rounding of `d`, or a uniform one. */
    private def near(d: Double): Long = fmt.tryEncode(d) match {
      case Some(b) if d > 0 =>
        val stepped = b + rnd.nextInt(5) - 2
        if (stepped >= 0 && fmt.isFinite(stepped) && fmt.sign(stepped) == 0) stepped else b
      case _ => uniform()
    }
    private def v(b: Long): Double = fmt.decode(b)
    /** Two patterns x >= y with y in [x/2, x], so that x - y is exact (Sterbenz). */
    private def closePair(): (Long, Long) = {
      val x = fmt.pack(0, anyExp(), mant())
      val y = fmt.tryEncode(v(x) * (0.5 + rnd.nextDouble() * 0.5)).filter(b => v(b) >= v(x) / 2 && v(b) <= v(x))
      (x, y.getOrElse(x))
    }
    /** A pattern of value x - y (exact by construction), or zero when it underflows. */
    private def difference(x: Long, y: Long): Long = fmt.tryEncode(v(x) - v(y)).getOrElse(0L)

    def next(): (Long, Long, Long) = rnd.nextInt(12) match {
      case 0 => (uniform(), uniform(), uniform())
      case 1 => val e = anyExp(); (withExp(e), withExp(e), withExp(e))
      case 2 => val (p, h) = (uniform(), uniform()); (p, h, near(v(p) - v(h)))
      case 3 => val (p, h) = (uniform(), uniform()); (p, h, near(v(p) + v(h)))
      case 4 => val (h, s) = (uniform(), uniform()); (near(v(h) + v(s)), h, s)
      case 5 => val (p, h) = closePair(); (p, h, difference(p, h)) // p - h = s
      case 6 => val (s, h) = closePair(); (difference(s, h), h, s) // p + h = s
      case 7 => // zeros, canonical or with a stray mantissa, in one or two positions
        val zero = () => if (rnd.nextBoolean()) 0L else fmt.pack(0, 0, mant())
        val t = Array(uniform(), uniform(), uniform())
        t(rnd.nextInt(3)) = zero(); if (rnd.nextInt(4) == 0) t(rnd.nextInt(3)) = zero()
        if (rnd.nextBoolean()) t(2) = t(0) // p = s with h = 0 or not: a tie either way
        (t(0), t(1), t(2))
      case 8 => // one operand far below the other two, which tie or sit one ulp apart
        val big = uniform(); val other = big + rnd.nextInt(3) - 1
        val o = if (other >= 0 && fmt.isFinite(other)) other else big
        val tiny = withExp(1 + rnd.nextInt(math.max(1, fmt.expField(big) / 2)))
        rnd.nextInt(3) match {
          case 0 => (big, tiny, o)
          case 1 => (tiny, big, o)
          case _ => (big, o, tiny)
        }
      case 9 => val e = fmt.expMax - 1 - rnd.nextInt(2); (withExp(e), withExp(e - rnd.nextInt(3)), withExp(e))
      case 10 => val e = 1 + rnd.nextInt(3); (withExp(e), withExp(e + rnd.nextInt(2)), withExp(e))
      case _ => val e = anyExp(); (withExp(e), withExp(math.max(1, e - rnd.nextInt(fmt.manWidth + 4))), withExp(e))
    }
  }
}
