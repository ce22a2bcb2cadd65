package mapm.sim

import mapm.model.FloatFormat

/** Exact, order-independent sums of format values, rounded to a double once: the frame
  * accumulation of the RTL render, identical to the Verilator harness's (tools/harness/accum.h),
  * so that the harness frame and the model frame are bit-equal whatever order the SOs arrive in.
  *
  * A value with exponent field E >= 1 and fraction M is the integer (2^m + M) * 2^(E-1) in units of
  * 2^(1 - bias - m). `count` sums are kept side by side as that integer in 32-bit limbs held in
  * Longs: an add puts less than 2^32 into each of two limbs, so carries are propagated every 2^30
  * adds. Exponent field 0 counts as zero (the formats flush subnormals); infinity or NaN makes
  * the sum NaN. [[toDouble]] rounds the exact sum to the nearest double, ties to even.
  * Formats up to 32 bits wide (the memory image's limit).
  */
final class ExactSum(val format: FloatFormat, val count: Int) {
  require(format.width <= 32, s"exact sums take formats of at most 32 bits, got $format")
  private val ew = format.expWidth
  private val mw = format.manWidth
  private val bias = (1 << (ew - 1)) - 1
  /** Limbs per sum: the widest value, plus room for carries and the sign. */
  val limbs: Int = ((1 << ew) + mw + 1) / 32 + 3
  private val limb = new Array[Long](count * limbs)
  private val adds = new Array[Int](count)
  private val nan = new Array[Boolean](count)

  /** Adds the format value `bits` to sum `i`. */
  def add(i: Int, bits: Long): Unit = {
    val e = ((bits >>> mw) & ((1L << ew) - 1)).toInt
    if (e == 0) return
    if (e == (1 << ew) - 1) { nan(i) = true; return }
    val sig = (1L << mw) | (bits & ((1L << mw) - 1))
    val shift = e - 1
    val v = sig << (shift % 32)
    val at = i * limbs + shift / 32
    val lo = v & 0xffffffffL; val hi = v >>> 32
    if (((bits >>> (ew + mw)) & 1) == 1) { limb(at) -= lo; limb(at + 1) -= hi }
    else { limb(at) += lo; limb(at + 1) += hi }
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
