package mapm.numerics

import java.math.BigInteger

/** Test reference, independent of [[SoftFloat]]: decodes bit patterns to exact rationals
  * (BigInteger numerator and denominator), does the operation exactly, and rounds the exact
  * rational with its own rounding routine (exact comparison of the remainder with one half, no
  * guard or sticky bits). It states the project conventions once more, from docs/fpu.md:
  * nearest-even rounding with unbounded exponent, then flush below the smallest normal to a zero
  * of the exact result's sign, overflow to infinity, exponent field 0 read as zero, canonical NaN.
  */
object ExactFloat {

  /** An operand or exact result: NaN, a signed infinity, or a finite rational num/den (num signed,
    * den > 0) with the sign of a zero kept in `negZero`. */
  sealed trait Value
  case object NaN extends Value
  final case class Inf(neg: Boolean) extends Value
  final case class Num(num: BigInteger, den: BigInteger, negZero: Boolean = false) extends Value {
    def isZero: Boolean = num.signum == 0
    def neg: Boolean = if (isZero) negZero else num.signum < 0
  }

  def decode(f: FloatFormat, bits: Long): Value = {
    val e = f.expField(bits)
    val neg = f.sign(bits) == 1
    if (e == f.expMax) { if (f.manField(bits) == 0) Inf(neg) else NaN }
    else if (e == 0) Num(BigInteger.ZERO, BigInteger.ONE, neg)
    else {
      val sig = BigInteger.valueOf((1L << f.manWidth) + f.manField(bits))
      val p = e - f.bias - f.manWidth // value = sig * 2^p
      val signed = if (neg) sig.negate else sig
      if (p >= 0) Num(signed.shiftLeft(p), BigInteger.ONE) else Num(signed, BigInteger.ONE.shiftLeft(-p))
    }
  }

  /** The bit pattern of an exact value: NaN canonical, infinities, signed zeros, and a nonzero
    * rational correctly rounded. */
  def encode(f: FloatFormat, v: Value): Long = v match {
    case NaN                        => f.quietNaN
    case Inf(neg)                   => f.pack(if (neg) 1 else 0, f.expMax, 0)
    case n: Num if n.isZero         => f.pack(if (n.neg) 1 else 0, 0, 0)
    case Num(num, den, _)           => round(f, num.signum < 0, num.abs, den)
  }

  /** Whether the nonzero rational |num|/den lies exactly halfway between two neighbours at the
    * format's precision (an exact rounding tie, before any flush or overflow). */
  def isTie(f: FloatFormat, v: Value): Boolean = v match {
    case Num(num, den, _) if num.signum != 0 =>
      val (sn, sd, _) = scaled(f, num.abs, den)
      sn.mod(sd).shiftLeft(1).equals(sd)
    case _ => false
  }

  /** num/den * 2^(manWidth - e) with e = floor(log2(num/den)), as (numerator, denominator, e). */
  private def scaled(f: FloatFormat, num: BigInteger, den: BigInteger): (BigInteger, BigInteger, Int) = {
    var e = num.bitLength - den.bitLength
    val below = if (e >= 0) num.compareTo(den.shiftLeft(e)) < 0 else num.shiftLeft(-e).compareTo(den) < 0
    if (below) e -= 1
    val k = f.manWidth - e
    if (k >= 0) (num.shiftLeft(k), den, e) else (num, den.shiftLeft(-k), e)
  }

  /** Correct rounding (nearest, ties to even) of the positive rational num/den, negated when
    * `neg`, with flush and overflow applied to the rounded value. */
  def round(f: FloatFormat, neg: Boolean, num: BigInteger, den: BigInteger): Long = {
    val s = if (neg) 1 else 0
    val (sn, sd, e0) = scaled(f, num, den)
    val qr = sn.divideAndRemainder(sd)
    val cmpHalf = qr(1).shiftLeft(1).compareTo(sd)
    var m = if (cmpHalf > 0 || (cmpHalf == 0 && qr(0).testBit(0))) qr(0).add(BigInteger.ONE) else qr(0)
    var e = e0
    if (m.bitLength > f.manWidth + 1) { m = m.shiftRight(1); e += 1 }
    if (e > f.maxExp) f.pack(s, f.expMax, 0)
    else if (e < f.minExp) f.pack(s, 0, 0)
    else f.pack(s, e + f.bias, m.longValue & f.manMask)
  }

  /** The exact sum of two values (IEEE rules for infinities and zero signs under nearest). */
  def sum(x: Value, y: Value): Value = (x, y) match {
    case (NaN, _) | (_, NaN)          => NaN
    case (Inf(a), Inf(b))             => if (a == b) Inf(a) else NaN
    case (i: Inf, _)                  => i
    case (_, i: Inf)                  => i
    case (a: Num, b: Num) =>
      val num = a.num.multiply(b.den).add(b.num.multiply(a.den))
      // A zero sum is -0 only when both addends are -0; x + (-x) is +0.
      Num(num, a.den.multiply(b.den), a.isZero && b.isZero && a.negZero && b.negZero)
  }

  def negate(x: Value): Value = x match {
    case NaN              => NaN
    case Inf(n)           => Inf(!n)
    case Num(num, den, z) => Num(num.negate, den, !z)
  }

  def product(x: Value, y: Value): Value = (x, y) match {
    case (NaN, _) | (_, NaN)                 => NaN
    case (a: Num, _: Inf) if a.isZero        => NaN
    case (_: Inf, b: Num) if b.isZero        => NaN
    case (a: Num, b: Num)                    => Num(a.num.multiply(b.num), a.den.multiply(b.den), a.neg != b.neg)
    case (a, b)                              => Inf(negative(a) != negative(b)) // an infinity times a nonzero
  }

  def quotient(x: Value, y: Value): Value = (x, y) match {
    case (NaN, _) | (_, NaN)                 => NaN
    case (_: Inf, _: Inf)                    => NaN
    case (a: Inf, b)                         => Inf(a.neg != negative(b))
    case (a, b: Inf)                         => Num(BigInteger.ZERO, BigInteger.ONE, negative(a) != b.neg)
    case (a: Num, b: Num) if b.isZero        => if (a.isZero) NaN else Inf(a.neg != b.neg)
    case (a: Num, b: Num) =>
      val num = a.num.multiply(b.den)
      val den = a.den.multiply(b.num)
      if (den.signum < 0) Num(num.negate, den.negate, a.neg != b.neg) else Num(num, den, a.neg != b.neg)
  }

  /** x < y on values; false when either is a NaN; zeros of both signs are equal. */
  def less(x: Value, y: Value): Boolean = (x, y) match {
    case (NaN, _) | (_, NaN)  => false
    case (Inf(a), Inf(b))     => a && !b
    case (Inf(a), _)          => a
    case (_, Inf(b))          => !b
    case (a: Num, b: Num)     => a.num.multiply(b.den).compareTo(b.num.multiply(a.den)) < 0
  }

  private def negative(v: Value): Boolean = v match {
    case Inf(n) => n
    case n: Num => n.neg
    case NaN    => false
  }

  // Rounded operations on bit patterns: the reference for SoftFloat and the hardware.
  def add(f: FloatFormat, a: Long, b: Long): Long = encode(f, sum(decode(f, a), decode(f, b)))
  def sub(f: FloatFormat, a: Long, b: Long): Long = encode(f, sum(decode(f, a), negate(decode(f, b))))
  def mul(f: FloatFormat, a: Long, b: Long): Long = encode(f, product(decode(f, a), decode(f, b)))
  def div(f: FloatFormat, a: Long, b: Long): Long = encode(f, quotient(decode(f, a), decode(f, b)))
  def lt(f: FloatFormat, a: Long, b: Long): Boolean = less(decode(f, a), decode(f, b))
}
