package mapm.sim

import mapm.numerics.FloatFormat

/** Exact, order-independent sums of format values, rounded to a double once: the frame
  * accumulation of the RTL render, identical to the Verilator harness's (tools/harness/accum.h),
  * so that the harness frame and the model frame are bit-equal whatever order the SOs arrive in.
  *
  * A value with exponent field E >= 1 and fraction M is the integer (2^m + M) * 2^(E-1) in units of
  * 2^(1 - bias - m). `count` sums are kept side by side as that integer in 32-bit limbs held in
  * Longs: the significand (2^m + M < 2^53) shifted by (E-1) % 32 spans up to three limbs, so an add
  * puts less than 2^32 into each of three limbs (starting at limb (E-1) / 32), and carries are
  * propagated every 2^30 adds. Exponent field 0 counts as zero (the formats flush subnormals);
  * infinity or NaN makes the sum NaN. [[toDouble]] rounds the exact sum to the nearest double,
  * ties to even. Every [[FloatFormat]] (up to 64 bits wide, e.g. fp64) is taken.
  */
final class ExactSum(val format: FloatFormat, val count: Int) {
  private val ew = format.expWidth
  private val mw = format.manWidth
  private val bias = (1 << (ew - 1)) - 1
  /** Limbs per sum. A value is below 2^(2^ew + m - 2), so it lies in limbs 0 to limbs - 3 (at least
    * 2^ew + m + 2 bits); the highest limb an add writes, (2^ew - 3) / 32 + 2, is at most limbs - 1,
    * and what it writes above limb limbs - 3 is zero. The two top limbs thus only gather carries
    * and the sign: after normalizing, the sum is a two's complement number of 32 * limbs bits
    * (at least 2^ew + m + 66), room for 2^67 adds of the largest value. */
  val limbs: Int = ((1 << ew) + mw + 1) / 32 + 3
  private val limb = new Array[Long](count * limbs)
  private val adds = new Array[Int](count)
  private val nan = new Array[Boolean](count)

  /** Adds the format value `bits` to sum `i`. */
  def add(i: Int, bits: Long): Unit = {
    val e = ((bits >>> mw) & ((1L << ew) - 1)).toInt
    if (e == 0) return
    if (e == (1 << ew) - 1) { nan(i) = true; return }
    val sig = (1L << mw) | (bits & ((1L << mw) - 1)) // < 2^53
    val shift = e - 1
    val r = shift % 32
    // sig << r (< 2^84) as three parts < 2^32: bits 0-31 and 32-63 of the 64-bit shift (the bits
    // it drops are the third part's), and bits 64-83 as (sig >> 32) >> (32 - r), whose shifts are
    // 32 at most: a single shift by 64 - r would be a shift by 0 at r = 0 (Java takes the amount
    // mod 64; C++ leaves it undefined), where the third part must be 0.
    val v = sig << r
    val p0 = v & 0xffffffffL
    val p1 = v >>> 32
    val p2 = (sig >>> 32) >>> (32 - r)
    val at = i * limbs + shift / 32
    if (((bits >>> (ew + mw)) & 1) == 1) { limb(at) -= p0; limb(at + 1) -= p1; limb(at + 2) -= p2 }
    else { limb(at) += p0; limb(at + 1) += p1; limb(at + 2) += p2 }
    adds(i) += 1
    if (adds(i) == (1 << 30)) { normalize(i); adds(i) = 0 }
  }

  private def normalize(i: Int): Unit = {
    val base = i * limbs
    var k = 0
    while (k + 1 < limbs) {
      val c = limb(base + k) >> 32
      limb(base + k) -= c << 32
      limb(base + k + 1) += c
      k += 1
    }
  }

  /** Sum `i` exactly, as a BigInt count of [[unit]]s (None when it is NaN). */
  def exact(i: Int): Option[BigInt] =
    if (nan(i)) None
    else Some((0 until limbs).foldLeft(BigInt(0))((s, k) => s + (BigInt(limb(i * limbs + k)) << (32 * k))))

  /** log2 of the unit [[exact]] counts. */
  def unitExp: Int = 1 - bias - mw

  /** Sum `i` rounded once to the nearest double (ties to even). */
  def toDouble(i: Int): Double = exact(i) match {
    case None => Double.NaN
    case Some(s) => ExactSum.round(s, unitExp)
  }
}

object ExactSum {
  /** The double nearest to v * 2^unitExp (ties to even), computed as the harness does it: a
    * 53-bit mantissa, round and sticky bits, then one scaling. */
  def round(v: BigInt, unitExp: Int): Double = {
    if (v == 0) return 0.0
    val mag = v.abs
    val top = mag.bitLength - 1
    val lowest = top - 52
    var mant = if (lowest >= 0) (mag >> lowest).toLong else (mag << -lowest).toLong
    val roundBit = lowest >= 1 && mag.testBit(lowest - 1)
    val sticky = lowest >= 2 && (mag & ((BigInt(1) << (lowest - 1)) - 1)) != 0
    if (roundBit && (sticky || (mant & 1) == 1)) mant += 1
    val r = java.lang.Math.scalb(mant.toDouble, lowest + unitExp)
    if (v < 0) -r else r
  }
}
