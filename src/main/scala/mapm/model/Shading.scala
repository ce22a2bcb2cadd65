package mapm.model

import mapm.MapmError

/** The arithmetic of one shader operation (dissertation 3.1.6 step 2 and 3.6.1), on bit patterns
  * of a float format:
  *  - cond: |q - p|^2 - h^2 < 0, whether photon p really lies within h of query q;
  *  - color: ((kernel * BRDF) / h) * power_c * contribution_c, for one colour channel c.
  *
  * Implementations: [[RoundedShadeArith]] (every operation rounded to the format), and later the
  * bit-accurate model of the online-arithmetic SOA, which only needs to implement `color`
  * (and a bit-exact soft-float `cond`) to plug into [[Render]].
  */
trait ShadeArith {
  def format: FloatFormat
  /** True when the squared distance between query (qx, qy, qz) and photon (px, py, pz) is below h^2. */
  def cond(qx: Long, qy: Long, qz: Long, px: Long, py: Long, pz: Long, h: Long): Boolean
  /** One colour channel of the shaded result, as a bit pattern of the format. */
  def color(kernel: Long, brdf: Long, h: Long, power: Long, contrib: Long): Long
}

object ShadeArith {
  /** The per-operation-rounded arithmetic in `format` (see [[RoundedShadeArith]] for the limits). */
  def rounded(format: FloatFormat): ShadeArith = new RoundedShadeArith(format)
  /** The float64 reference path: the same, in binary64 (native double arithmetic). */
  def float64: ShadeArith = new RoundedShadeArith(FloatFormat.fp64)
}

/** Shader arithmetic with each operation rounded to the format (nearest, ties to even; results
  * below the smallest normal flush to zero) in this fixed order:
  *
  *   cond:  dx = R(qx - px), dy = R(qy - py), dz = R(qz - pz)
  *          d2 = R(R(R(dx*dx) + R(dy*dy)) + R(dz*dz)),  h2 = R(h*h)
  *          cond = sign bit of R(d2 - h2)
  *   color: t1 = R(kernel * BRDF), t2 = R(t1 / h), t3 = R(t2 * power), color = R(t3 * contribution)
  *
  * cond: R preserves the sign of an exact difference and d2 - h2 is zero only when d2 == h2, so
  * the last step is exactly the comparison d2 < h2. A square that overflows becomes +infinity,
  * which correctly fails the test; h^2 itself must fit (checked by [[PhotonMap]]).
  *
  * color: follows the SOA's output rules for zero and range: a zero kernel, BRDF, power or
  * contribution gives +0 (h must be non-zero), an overflowing result saturates to the largest
  * finite value, and a result that flushes is +0. (Intermediates follow IEEE: an overflow is an
  * infinity and stays one, an underflow is zero and stays one, so no NaN can arise.)
  *
  * Each operation is computed in binary64 and then rounded to the format. That double rounding is
  * exactly the single rounding of the real result only when 53 >= 2p + 2 with p = manWidth + 1
  * (Figueroa's condition for +, -, *, /), i.e. manWidth <= 24, and when binary64's exponent range
  * covers every product and quotient of two format values, i.e. expWidth <= 10. fp64 itself is
  * allowed: its operations round once, natively. Other formats are a [[MapmError]].
  */
final class RoundedShadeArith(val format: FloatFormat) extends ShadeArith {
  private val m = format.manWidth
  private val native = format == FloatFormat.fp64
  MapmError.check(native || (2 * (m + 1) + 2 <= 53 && format.expWidth <= 10),
    s"format $format: the rounded shading path computes in binary64 and rounds each operation, which is exact " +
      s"only for mantissa width <= 24 and exponent width <= 10 (or fp64 itself)")
  private val drop = 52 - m
  private val dropMask = if (native) 0L else (1L << drop) - 1
  private val halfMinus1 = if (native) 0L else (1L << (drop - 1)) - 1
  private val minNormal = format.minNormal
  private val maxFinite = format.maxFinite
  private val maxBits = format.pack(0, format.expMax - 1, format.manMask)
  private val bias = format.bias
  private val manMask = format.manMask
  private val expMax = format.expMax

  /** `d` rounded to the format: nearest even, flushed to a signed zero below the smallest normal,
    * an infinity of the same sign above the largest finite value. */
  def round(d: Double): Double = {
    var r = d
    if (!native) {
      val b = java.lang.Double.doubleToRawLongBits(d)
      val lsb = (b >>> drop) & 1L
      r = java.lang.Double.longBitsToDouble((b + halfMinus1 + lsb) & ~dropMask)
    }
    val a = java.lang.Math.abs(r)
    if (a < minNormal) java.lang.Math.copySign(0.0, d)
    else if (a > maxFinite) java.lang.Math.copySign(Double.PositiveInfinity, d)
    else r
  }

  /** Value of a bit pattern (exponent field 0 reads as a signed zero). */
  def toDouble(bits: Long): Double = {
    val e = (bits >>> m) & format.expMask
    val sign = (bits >>> (format.width - 1)) & 1L
    if (e == 0) { if (sign == 0) 0.0 else -0.0 }
    else if (e == expMax) format.decode(bits)
    else java.lang.Double.longBitsToDouble((sign << 63) | ((e - bias + 1023) << 52) | ((bits & manMask) << drop))
  }

  /** Bit pattern of a finite value already in the format (zero, or normal and in range). */
  def toBits(d: Double): Long = {
    val b = java.lang.Double.doubleToRawLongBits(d)
    val sign = b >>> 63
    val e = (b >>> 52) & 0x7ffL
    if (e == 0) sign << (format.width - 1)
    else (sign << (format.width - 1)) | ((e - 1023 + bias) << m) | ((b >>> drop) & manMask)
  }

  def cond(qx: Long, qy: Long, qz: Long, px: Long, py: Long, pz: Long, h: Long): Boolean = {
    val dx = round(toDouble(qx) - toDouble(px))
    val dy = round(toDouble(qy) - toDouble(py))
    val dz = round(toDouble(qz) - toDouble(pz))
    val d2 = round(round(round(dx * dx) + round(dy * dy)) + round(dz * dz))
    val hv = toDouble(h)
    d2 < round(hv * hv)
  }

  def color(kernel: Long, brdf: Long, h: Long, power: Long, contrib: Long): Long = {
    val k = toDouble(kernel); val b = toDouble(brdf); val p = toDouble(power); val c = toDouble(contrib)
    if (k == 0 || b == 0 || p == 0 || c == 0) return 0L
    val r = round(round(round(round(k * b) / toDouble(h)) * p) * c)
    if (r == 0) 0L
    else if (r.isInfinite) maxBits | (if (r < 0) 1L << (format.width - 1) else 0L)
    else toBits(r)
  }
}

/** The per-photon shading constants stored with every photon (the hardware fetches them through
  * the photon cache, Table 4.1). See docs/shading.md for the derivation.
  *
  * With BRDF = 1/pi and kernel = 1/(pi h), one shader operation gives
  * power * contribution / (pi^2 h^2): the Lambertian reflection 1/pi (the surfaces' diffuse
  * colours and the 1/N of final gathering ride in the query point's contribution) times a constant
  * disc kernel, kernel / h = 1 / (pi h^2) = 1 / (area of the disc of radius h).
  */
object Shading {
  /** Lambertian BRDF normalisation, 1/pi. */
  val brdf: Double = 1.0 / math.Pi
  /** Constant disc kernel for radius h, 1/(pi h), so that kernel / h = 1/(pi h^2). */
  def kernel(h: Double): Double = 1.0 / (math.Pi * h)
}
