package mapm.numerics

import mapm.MapmError

/** A radix-2 signed-digit string d_1 … d_length with digits in {−1, 0, +1}, most significant
  * first, read as the fraction Σ d_i·2^-i (online-arithmetic.md §0).
  *
  * Held as two bit masks so that a whole string costs two Longs: digit i sits at bit
  * `length − i` of `pos` when it is +1 and of `neg` when it is −1 (never both). Hence
  * `pos − neg` is the string's value scaled by 2^length, an exact two's-complement integer.
  */
final case class DigitString(pos: Long, neg: Long, length: Int) {
  require(length >= 0 && length <= DigitString.MaxLength, s"digit string length $length outside 0..${DigitString.MaxLength}")
  require((pos & neg) == 0, "a digit cannot be +1 and −1 at once")

  /** Digit i (1-based); 0 beyond the end. */
  def digit(i: Int): Int =
    if (i < 1 || i > length) 0
    else (((pos >>> (length - i)) & 1L) - ((neg >>> (length - i)) & 1L)).toInt

  /** The value times 2^length. */
  def scaled: Long = pos - neg

  /** The value as a Double (exact for lengths up to 53). */
  def toDouble: Double = java.lang.Math.scalb(scaled.toDouble, -length)

  /** The vector notation: one character per digit, `+`, `0` or `-`, most significant first. */
  override def toString: String = {
    val sb = new StringBuilder(length)
    var i = 1
    while (i <= length) { sb += (digit(i) match { case 1 => '+'; case -1 => '-'; case _ => '0' }); i += 1 }
    sb.toString
  }
}

object DigitString {
  /** Longest string two Longs hold with `pos − neg` still exact. */
  val MaxLength = 62

  val empty: DigitString = DigitString(0L, 0L, 0)

  /** The n bits of `bits` (bit n−1 first) as digits 0 and +1. */
  def ofBits(bits: Long, n: Int): DigitString = DigitString(bits & ((1L << n) - 1), 0L, n)

  /** Reads the vector notation (`+`, `0`, `-`); anything else is a [[MapmError]]. */
  def parse(text: String): DigitString = {
    MapmError.check(text.length <= MaxLength, s"digit string '$text' is longer than $MaxLength digits")
    var p = 0L; var n = 0L
    for (c <- text) {
      p <<= 1; n <<= 1
      c match {
        case '+' => p |= 1L
        case '-' => n |= 1L
        case '0' =>
        case _   => MapmError.fail(s"digit string '$text': '$c' is not one of + 0 -")
      }
    }
    DigitString(p, n, text.length)
  }
}
