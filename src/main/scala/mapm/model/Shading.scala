package mapm.model

import mapm.numerics._

import mapm.MapmError

/** The arithmetic of one shader operation (dissertation 3.1.6 step 2 and 3.6.1), on bit patterns
  * of a float format:
  *  - cond: |q - p|^2 - h^2 < 0, whether photon p really lies within h of query q;
  *  - color: ((kernel * BRDF) / h) * power_c * contribution_c, for one colour channel c.
  *
  * Implementations: [[RoundedShadeArith]] (every operation rounded to the format; the float64
  * reference path) and [[HardwareShadeArith]] (the SOA bit for bit: the online colour chain
  * [[ShaderChainModel]] and the correctly rounded [[CondModel]]).
  */
trait ShadeArith {
  def format: FloatFormat
  /** True when the squared distance between query (qx, qy, qz) and photon (px, py, pz) is below h^2. */
  def cond(qx: Long, qy: Long, qz: Long, px: Long, py: Long, pz: Long, h: Long): Boolean
  /** One colour channel of the shaded result, as a bit pattern of the format. */
  def color(kernel: Long, brdf: Long, h: Long, power: Long, contrib: Long): Long
  /** The three channels of one shader operation into out(0), out(1), out(2) (red, green, blue).
    * Must equal [[color]] per channel; an implementation may compute the shared kernel * BRDF / h
    * part once, as the SOA does. */
  def shade(kernel: Long, brdf: Long, h: Long, pr: Long, pg: Long, pb: Long, cr: Long, cg: Long, cb: Long,
            out: Array[Long]): Unit = {
    out(0) = color(kernel, brdf, h, pr, cr); out(1) = color(kernel, brdf, h, pg, cg); out(2) = color(kernel, brdf, h, pb, cb)
  }
  /** [[shade]] with the three channels as the values of their bit patterns (the doubles that hold
    * them exactly, as [[FloatFormat.decode]] reads them) into values(0), values(1), values(2), for a
    * caller that adds them up. `bits` is scratch space of at least three slots; what it holds
    * afterwards is unspecified. The default shades into `bits` and decodes; an implementation that
    * has the values at hand may skip the bit patterns. */
  def shadeValues(kernel: Long, brdf: Long, h: Long, pr: Long, pg: Long, pb: Long, cr: Long, cg: Long, cb: Long,
                  bits: Array[Long], values: Array[Double]): Unit = {
    shade(kernel, brdf, h, pr, pg, pb, cr, cg, cb, bits)
    values(0) = format.decode(bits(0)); values(1) = format.decode(bits(1)); values(2) = format.decode(bits(2))
  }
  /** Bounds (lo, hi) on the EXACT squared distance d2 = |q - p|^2 (of the format values) for radius
    * h: [[cond]] is true whenever d2 < lo and false whenever d2 > hi. [[Render]] decides those clear
    * cases with plain double arithmetic and calls [[cond]] only in between. The default promises
    * nothing, so every shader operation goes through [[cond]]. */
  def condClearBounds(h: Long): (Double, Double) = (Double.NegativeInfinity, Double.PositiveInfinity)
  /** Whether [[shadeFlags]] models the SOA's per-channel flags. */
  def hasFlags: Boolean = false
  /** [[shade]], and the SOA's flags of each channel (OVF 1, UNF 2, INV 4) into flags(0..2). Only
    * for an arithmetic with [[hasFlags]]; the others have no flags to report and throw. */
  def shadeFlags(kernel: Long, brdf: Long, h: Long, pr: Long, pg: Long, pb: Long, cr: Long, cg: Long, cb: Long,
                 out: Array[Long], flags: Array[Int]): Unit =
    throw new UnsupportedOperationException(s"${getClass.getSimpleName} does not model the SOA's flags")
}

object ShadeArith {
  /** The per-operation-rounded arithmetic in `format` (see [[RoundedShadeArith]] for the limits). */
  def rounded(format: FloatFormat): ShadeArith = new RoundedShadeArith(format)
  /** The float64 reference path: the same, in binary64 (native double arithmetic). */
  def float64: ShadeArith = new RoundedShadeArith(FloatFormat.fp64)
  /** The SOA's arithmetic bit for bit, with `g` guard digits in the online colour chain. */
  def hardware(format: FloatFormat, g: Int): ShadeArith = new HardwareShadeArith(format, g)
  /** The conventional SOA's arithmetic bit for bit ([[ConvShadeArith]]). */
  def conventional(format: FloatFormat): ShadeArith = new ConvShadeArith(format)
  /** The SOA's arithmetic of either kind, bit for bit. */
  def hardware(format: FloatFormat, g: Int, arith: Arith): ShadeArith = arith match {
    case Arith.Online => hardware(format, g)
    case Arith.Conventional => conventional(format)
  }
}

object RoundedShadeArith {
  /** The shared part t2 = R(R(kernel * BRDF) / h) of the last (kernel, BRDF, h) shaded. */
  private final class Prefix(val kernel: Long, val brdf: Long, val h: Long, val t2: Double)

  /** Whether [[RoundedShadeArith.round]] may round through binary32 (`Double.toFloat`): for
    * formats with binary32's 23 fraction bits and an exponent range inside binary32's. */
  def roundsViaFloat(format: FloatFormat): Boolean = format.manWidth == 23 && format.expWidth <= 8

  /** `format` when the rounded path can do it exactly (see [[RoundedShadeArith]]), else a [[MapmError]]. */
  def checked(format: FloatFormat): FloatFormat = {
    MapmError.check(format == FloatFormat.fp64 || (2 * (format.manWidth + 1) + 2 <= 53 && format.expWidth <= 10),
      s"format $format: the rounded shading path computes in binary64 and rounds each operation, which is exact " +
        s"only for mantissa width <= 24 and exponent width <= 10 (or fp64 itself)")
    format
  }
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
  * [[condClearBounds]]: each of the five roundings on the way to d2 is within a factor (1 -/+ u)
  * (u = 2^-(manWidth+1)), and flushed terms add less than 5 smallest normals, so the chain's d2 lies
  * within d2_exact * (1 -/+ u)^5 -/+ 5 * minNormal; bounds with (1 -/+ u)^6 and 8 * minNormal are safe.
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
  *
  * Speed: formats with 23 fraction bits and at most 8 exponent bits (fp32) round through binary32
  * (`toFloat`, round to nearest even in hardware) whenever the result is a normal, finite value of
  * the format, and through the bit arithmetic of [[roundByBits]] otherwise (flush, overflow), which
  * gives the same bits (see [[round]]); fp32 inputs decode through `intBitsToFloat` when they are
  * normal and finite (see [[decode]]). The shared t2 of the last (kernel, BRDF, h) is kept and
  * reused while they repeat (one record behind an atomic reference, which starts as (0, 0, 0) with
  * t2 = 0, the value [[prefix]] gives for a zero kernel: thread-safe, a thread that misses
  * recomputes the same value). [[shadeValues]] hands the channel values to the engine
  * without packing them into bit patterns.
  */
final class RoundedShadeArith private (
    val format: FloatFormat,
    // Constants of the format, as constructor parameters: plain fields (class-body vals would get
    // -Xcheckinit accessors, which keep the JIT from inlining the per-operation code).
    codec: FormatBits,
    native: Boolean,
    viaFloat: Boolean,
    binary32: Boolean,
    drop: Int,
    dropMask: Long,
    halfMinus1: Long,
    minNormal: Double,
    maxFinite: Double,
    condHi: Double,
    condLo: Double,
    condAbs: Double,
    last: java.util.concurrent.atomic.AtomicReference[RoundedShadeArith.Prefix]
) extends ShadeArith {
  def this(format: FloatFormat) = this(RoundedShadeArith.checked(format), new FormatBits(format), format == FloatFormat.fp64,
    RoundedShadeArith.roundsViaFloat(format), format == FloatFormat.fp32,
    52 - format.manWidth, (1L << (52 - format.manWidth)) - 1, (1L << (52 - format.manWidth)) / 2 - 1 max 0L,
    format.minNormal, format.maxFinite,
    math.pow(1 + math.pow(2, -format.manWidth - 1), 6) * (1 + 1e-12),
    math.pow(1 - math.pow(2, -format.manWidth - 1), 6) * (1 - 1e-12),
    8 * format.minNormal, new java.util.concurrent.atomic.AtomicReference(new RoundedShadeArith.Prefix(0L, 0L, 0L, 0.0)))

  /** `d` rounded to the format: nearest even, flushed to a signed zero below the smallest normal,
    * an infinity of the same sign above the largest finite value; bit for bit [[roundByBits]].
    *
    * Through binary32 when [[RoundedShadeArith.roundsViaFloat]]: if f = `d.toFloat` (nearest even to
    * 24 significant bits wherever |d| is a binary32 normal) lies strictly above the format's smallest
    * normal and at most its largest finite value, then so does d (rounding is monotone and both
    * bounds are binary32 values), d is a binary32 normal, and f is what [[roundByBits]] gives. Any
    * other f (at or below the smallest normal, beyond the largest finite value, an infinity, NaN)
    * goes to [[roundByBits]]. */
  def round(d: Double): Double =
    if (viaFloat) {
      val f = d.toFloat.toDouble
      val a = java.lang.Math.abs(f)
      if (a > minNormal && a <= maxFinite) f else roundByBits(d)
    } else roundByBits(d)

  /** [[round]] by bit arithmetic on the binary64 pattern: the mantissa rounded to the format's width
    * (nearest even; a carry moves into the exponent), then flush or overflow by magnitude. */
  def roundByBits(d: Double): Double = {
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

  def cond(qx: Long, qy: Long, qz: Long, px: Long, py: Long, pz: Long, h: Long): Boolean = {
    val c = codec
    val hv = c.toDouble(h)
    val dx = round(c.toDouble(qx) - c.toDouble(px))
    val dy = round(c.toDouble(qy) - c.toDouble(py))
    val dz = round(c.toDouble(qz) - c.toDouble(pz))
    round(round(round(dx * dx) + round(dy * dy)) + round(dz * dz)) < round(hv * hv)
  }

  override def condClearBounds(h: Long): (Double, Double) = {
    val hv = codec.toDouble(h)
    val h2 = round(hv * hv)
    if (h2.isInfinite) super.condClearBounds(h) else ((h2 - condAbs) / condHi, (h2 + condAbs) / condLo)
  }

  /** t2 = R(R(kernel * BRDF) / h), the part shared by the three channels; 0 when a factor is 0. */
  private def prefix(kernel: Long, brdf: Long, h: Long): Double = {
    val k = decode(kernel); val b = decode(brdf)
    if (k == 0 || b == 0) 0.0 else round(round(k * b) / decode(h))
  }

  /** [[prefix]] through the one-record cache of the last (kernel, BRDF, h). */
  private def cachedPrefix(kernel: Long, brdf: Long, h: Long): Double = {
    val c = last.get
    if (c.kernel == kernel && c.brdf == brdf && c.h == h) c.t2
    else {
      val t2 = prefix(kernel, brdf, h)
      last.set(new RoundedShadeArith.Prefix(kernel, brdf, h, t2))
      t2
    }
  }

  /** The value of a bit pattern, as [[FormatBits.toDouble]] reads it. For fp32, whose patterns are
    * binary32's, through `intBitsToFloat` when that gives a normal, finite value (binary32 and fp32
    * agree on those); zero and denormal fields (which read as zero here), infinities and NaNs take
    * the general decoder. */
  def decode(bits: Long): Double =
    if (binary32) {
      val f = java.lang.Float.intBitsToFloat(bits.toInt)
      val a = java.lang.Math.abs(f)
      if (a >= java.lang.Float.MIN_NORMAL && a <= java.lang.Float.MAX_VALUE) f.toDouble else codec.toDouble(bits)
    } else codec.toDouble(bits)

  /** The value of [[finish]]'s bit pattern: 0.0, the signed largest finite value, or the result. */
  private def finishValue(t2: Double, power: Long, contrib: Long): Double = {
    val p = decode(power); val c = decode(contrib)
    if (t2 == 0 || p == 0 || c == 0) return 0.0
    val r = round(round(t2 * p) * c)
    if (r == 0) 0.0
    else if (r.isInfinite) java.lang.Math.copySign(maxFinite, r)
    else r
  }

  /** R(R(t2 * power) * contribution) with the output rules (zero, saturation). */
  private def finish(t2: Double, power: Long, contrib: Long): Long = {
    val v = finishValue(t2, power, contrib)
    if (v == 0) 0L else codec.toBits(v)
  }

  def color(kernel: Long, brdf: Long, h: Long, power: Long, contrib: Long): Long =
    finish(prefix(kernel, brdf, h), power, contrib)

  override def shade(kernel: Long, brdf: Long, h: Long, pr: Long, pg: Long, pb: Long, cr: Long, cg: Long, cb: Long,
                     out: Array[Long]): Unit = {
    val t2 = cachedPrefix(kernel, brdf, h)
    out(0) = finish(t2, pr, cr); out(1) = finish(t2, pg, cg); out(2) = finish(t2, pb, cb)
  }

  override def shadeValues(kernel: Long, brdf: Long, h: Long, pr: Long, pg: Long, pb: Long, cr: Long, cg: Long, cb: Long,
                           bits: Array[Long], values: Array[Double]): Unit = {
    val t2 = cachedPrefix(kernel, brdf, h)
    values(0) = finishValue(t2, pr, cr); values(1) = finishValue(t2, pg, cg); values(2) = finishValue(t2, pb, cb)
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
