package mapm.numerics

import mapm.MapmError

/** An IEEE-754-style binary floating-point format with `expWidth` exponent bits and `manWidth`
  * stored mantissa (fraction) bits, one sign bit and a hidden leading one.
  *
  * Conventions shared by the model and the hardware:
  *  - Exponent field 0 is zero (denormals are flushed: any result below the smallest normal
  *    becomes a signed zero).
  *  - Exponent field all-ones is infinity (mantissa 0) or NaN; [[encode]] rejects both.
  *  - Conversion from Double rounds to nearest, ties to even.
  *
  * Bit patterns are held in a `Long` (the widest format, 11+52+1 bits, fills it exactly).
  */
final case class FloatFormat(expWidth: Int, manWidth: Int) {
  require(expWidth >= 2 && expWidth <= 11, s"exponent width must be 2..11, got $expWidth")
  require(manWidth >= 1 && manWidth <= 52, s"mantissa width must be 1..52, got $manWidth")

  /** Total width in bits: sign, exponent, mantissa. */
  val width: Int = 1 + expWidth + manWidth
  /** Exponent bias, 2^(expWidth-1) - 1. */
  val bias: Int = (1 << (expWidth - 1)) - 1
  /** The all-ones exponent field (infinity / NaN). */
  val expMax: Int = (1 << expWidth) - 1
  /** Largest and smallest unbiased exponent of a normal number. */
  val maxExp: Int = expMax - 1 - bias
  val minExp: Int = 1 - bias
  val manMask: Long = (1L << manWidth) - 1
  val expMask: Long = expMax.toLong
  /** Mask of all `width` bits. */
  val mask: Long = if (width == 64) -1L else (1L << width) - 1

  /** Short name, e.g. `e8m23`; used in module and file names. */
  def name: String = s"e${expWidth}m$manWidth"
  override def toString: String = FloatFormat.presetName(this).getOrElse(name)

  def sign(bits: Long): Int = ((bits >>> (width - 1)) & 1L).toInt
  def expField(bits: Long): Int = ((bits >>> manWidth) & expMask).toInt
  def manField(bits: Long): Long = bits & manMask
  def pack(sign: Int, exp: Int, man: Long): Long =
    ((sign.toLong & 1L) << (width - 1)) | ((exp.toLong & expMask) << manWidth) | (man & manMask)

  def isZero(bits: Long): Boolean = expField(bits) == 0
  def isInf(bits: Long): Boolean = expField(bits) == expMax && manField(bits) == 0
  def isNaN(bits: Long): Boolean = expField(bits) == expMax && manField(bits) != 0
  def isFinite(bits: Long): Boolean = expField(bits) != expMax

  /** Largest finite value, smallest normal value. */
  def maxFinite: Double = decode(pack(0, expMax - 1, manMask))
  def minNormal: Double = math.pow(2.0, minExp.toDouble)
  /** The canonical quiet NaN and +infinity patterns (hardware outputs only). */
  def quietNaN: Long = pack(0, expMax, 1L << (manWidth - 1))
  def posInf: Long = pack(0, expMax, 0)

  /** Value of a bit pattern. Exponent field 0 reads as (signed) zero whatever the mantissa. */
  def decode(bits: Long): Double = {
    val s = sign(bits); val e = expField(bits); val m = manField(bits)
    val v =
      if (e == 0) 0.0
      else if (e == expMax) { if (m == 0) Double.PositiveInfinity else Double.NaN }
      else java.lang.Math.scalb(((1L << manWidth) | m).toDouble, e - bias - manWidth)
    if (s == 1) -v else v
  }

  /** Rounds `d` to this format (nearest, ties to even; below the smallest normal flushes to a
    * signed zero). Returns None for NaN, infinity and values that overflow the format. */
  def tryEncode(d: Double): Option[Long] = {
    val b = encodeOr(d, -1L)
    if (b == -1L) None else Some(b)
  }

  /** [[tryEncode]] without an Option, for hot loops: the bit pattern, or `none` for NaN, infinity
    * and values that overflow. Every pattern it returns is a finite value's, so -1 (bits beyond
    * the width, or fp64's all-ones NaN) serves as `none`. */
  def encodeOr(d: Double, none: Long): Long = {
    if (d.isNaN || d.isInfinite) return none
    val raw = java.lang.Double.doubleToRawLongBits(d)
    val s = (raw >>> 63).toInt
    val de = ((raw >>> 52) & 0x7ff).toInt
    if (de == 0) return pack(s, 0, 0) // zero or double denormal: flushed
    val frac52 = raw & ((1L << 52) - 1)
    val drop = 52 - manWidth
    var sig = (1L << 52 | frac52) >>> drop // 1.m with manWidth fraction bits
    var e = de - 1023
    if (drop > 0) {
      val rem = frac52 & ((1L << drop) - 1)
      val half = 1L << (drop - 1)
      if (rem > half || (rem == half && (sig & 1L) == 1L)) sig += 1
      if (sig >>> (manWidth + 1) != 0) { sig >>>= 1; e += 1 }
    }
    if (e < minExp) pack(s, 0, 0)
    else if (e > maxExp) none
    else pack(s, e + bias, sig & manMask)
  }

  /** Like [[tryEncode]] but a NaN, infinite or overflowing value is a [[MapmError]] naming `what`. */
  def encode(d: Double, what: => String = "value"): Long = tryEncode(d) match {
    case Some(b) => b
    case None =>
      if (d.isNaN) MapmError.fail(s"$what is NaN, which format $this cannot carry")
      else if (d.isInfinite) MapmError.fail(s"$what is infinite, which format $this cannot carry")
      else MapmError.fail(f"$what = $d%g overflows format $this (largest finite value $maxFinite%g)")
  }

  /** `d` rounded to this format and back. */
  def quantize(d: Double, what: => String = "value"): Double = decode(encode(d, what))

  /** Unit in the last place of a normal number with unbiased exponent `e`. */
  def ulpAt(e: Int): Double = math.pow(2.0, (e - manWidth).toDouble)

  /** Hex string of a bit pattern, zero-padded to the format width. */
  def hex(bits: Long): String = {
    val digits = (width + 3) / 4
    val h = java.lang.Long.toHexString(bits & mask)
    "0" * (digits - h.length) + h
  }
}

object FloatFormat {
  val fp32 = FloatFormat(8, 23)
  val bf16 = FloatFormat(8, 7)
  val fp16 = FloatFormat(5, 10)
  val fp24 = FloatFormat(8, 15)
  val fp64 = FloatFormat(11, 52)

  val presets: Seq[(String, FloatFormat)] =
    Seq("fp32" -> fp32, "bf16" -> bf16, "fp16" -> fp16, "fp24" -> fp24, "fp64" -> fp64)

  def presetName(f: FloatFormat): Option[String] = presets.collectFirst { case (n, p) if p == f => n }

  /** Parses `fp32`, `bf16`, `fp16`, `fp24`, `fp64`, `E,M` or `eEmM`; a [[MapmError]] otherwise. */
  def parse(text: String): FloatFormat = {
    val t = text.trim.toLowerCase
    val em = "e(\\d+)m(\\d+)".r
    val pair = "(\\d+)\\s*,\\s*(\\d+)".r
    def make(e: Int, m: Int): FloatFormat = {
      MapmError.check(e >= 2 && e <= 11, s"format '$text': exponent width must be 2..11")
      MapmError.check(m >= 1 && m <= 52, s"format '$text': mantissa width must be 1..52")
      FloatFormat(e, m)
    }
    presets.collectFirst { case (n, f) if n == t => f }.getOrElse(t match {
      case em(e, m)   => make(e.toInt, m.toInt)
      case pair(e, m) => make(e.toInt, m.toInt)
      case _ =>
        MapmError.fail(s"unknown float format '$text' (use ${presets.map(_._1).mkString(", ")} or E,M)")
    })
  }
}
