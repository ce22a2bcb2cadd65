package mapm.numerics

/** Fast conversion between bit patterns of a float format and the doubles that hold their values
  * exactly (the model's hot loops; [[FloatFormat.decode]] is the general, slower reference).
  * Needs expWidth <= 11 and manWidth <= 52, which every [[FloatFormat]] satisfies.
  */
final class FormatBits private (
    val format: FloatFormat,
    // plain constructor fields rather than class-body vals, which -Xcheckinit would wrap in checks
    m: Int,
    drop: Int,
    bias: Int,
    manMask: Long,
    expMask: Long,
    expMax: Int,
    signShift: Int
) {
  def this(format: FloatFormat) =
    this(format, format.manWidth, 52 - format.manWidth, format.bias, format.manMask, format.expMask, format.expMax, format.width - 1)

  /** Value of a bit pattern (exponent field 0 reads as a signed zero, as in [[FloatFormat.decode]]). */
  def toDouble(bits: Long): Double = {
    val e = (bits >>> m) & expMask
    val sign = (bits >>> signShift) & 1L
    if (e == 0) { if (sign == 0) 0.0 else -0.0 }
    else if (e == expMax) special(bits)
    else java.lang.Double.longBitsToDouble((sign << 63) | ((e - bias + 1023) << 52) | ((bits & manMask) << drop))
  }

  /** Infinity or NaN (out of line: never on the hot path). */
  private def special(bits: Long): Double = format.decode(bits)

  /** Bit pattern of a value that the format holds exactly (zero, or normal and in range). */
  def toBits(d: Double): Long = {
    val b = java.lang.Double.doubleToRawLongBits(d)
    val sign = b >>> 63
    val e = (b >>> 52) & 0x7ffL
    if (e == 0) sign << signShift
    else (sign << signShift) | ((e - 1023 + bias) << m) | ((b >>> drop) & manMask)
  }
}
