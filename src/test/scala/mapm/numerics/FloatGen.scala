package mapm.numerics

/** Seeded generator of operands that reach the hard cases of floating-point arithmetic in format
  * `f`: arbitrary patterns (denormals, infinities, NaNs), exponents at both extremes, short
  * mantissas, and operand pairs built for cancellation, equality and exact rounding ties. */
final class FloatGen(f: FloatFormat, seed: Long) {
  val rnd = new scala.util.Random(seed)
  private val n = f.manWidth + 1

  def bits(): Long = rnd.nextLong() & f.mask
  def sign(): Int = rnd.nextInt(2)
  def mantissa(): Long = rnd.nextLong() & f.manMask
  /** A biased exponent field of a normal number within [lo, hi], clamped to the normal range. */
  def expIn(lo: Int, hi: Int): Int = {
    val a = math.max(1, lo); val b = math.min(f.expMax - 1, hi)
    if (a >= b) math.max(1, math.min(f.expMax - 1, a)) else a + rnd.nextInt(b - a + 1)
  }
  def clampExp(e: Int): Int = math.max(1, math.min(f.expMax - 1, e))
  /** A normal number near 1.0 (exponent within `spread` of the bias). */
  def normalNear1(spread: Int): Long = f.pack(sign(), expIn(f.bias - spread, f.bias + spread), mantissa())
  /** A mantissa field whose fraction has only its top `t` bits random. */
  def shortMantissa(t: Int): Long = if (t >= f.manWidth) mantissa() else (rnd.nextLong() & ((1L << t) - 1)) << (f.manWidth - t)

  /** One operand from a mixture of patterns. */
  def operand(): Long = rnd.nextInt(20) match {
    case 0 | 1 | 2 | 3 => bits()
    case 4             => f.pack(sign(), 0, if (rnd.nextBoolean()) 0 else mantissa()) // zero or denormal pattern
    case 5             => f.pack(sign(), f.expMax, if (rnd.nextInt(3) == 0) mantissa() else 0) // inf or NaN
    case 6 | 7         => f.pack(sign(), expIn(f.expMax - 4, f.expMax), mantissa())
    case 8 | 9         => f.pack(sign(), expIn(1, 4), mantissa())
    case 10 | 11       => f.pack(sign(), expIn(f.bias - 8, f.bias + 8), shortMantissa(rnd.nextInt(4)))
    case _             => normalNear1(12)
  }

  /** A pair of operands, often related so that addition, multiplication or comparison is hard. */
  def pair(): (Long, Long) = {
    val a = operand()
    rnd.nextInt(16) match {
      case 0 | 1 | 2 => (a, operand())
      case 3 => (a, a)
      case 4 => (a, a ^ (1L << (f.width - 1))) // negation
      case 5 => (a, a ^ (rnd.nextLong() & ((1L << math.max(1, f.manWidth / 2)) - 1))) // low bits differ
      case 6 | 7 => // exponents within 2: cancellation in subtraction
        val ea = expIn(2, f.expMax - 2)
        (f.pack(sign(), ea, mantissa()), f.pack(sign(), expIn(ea - 2, ea + 2), mantissa()))
      case 8 | 9 => addTie()
      case 10 | 11 => mulTie()
      case 12 => // products near overflow or underflow
        val e = if (rnd.nextBoolean()) f.expMax - 1 else 1
        val ea = expIn(f.bias + (e - f.bias) / 2 - 2, f.bias + (e - f.bias) / 2 + 2)
        (f.pack(sign(), ea, mantissa()), f.pack(sign(), clampExp(e - ea + f.bias + rnd.nextInt(3) - 1), mantissa()))
      case 13 => // product near 1.0 * 2^minExp boundary
        val ea = expIn(1, f.bias)
        (f.pack(sign(), ea, f.manMask - rnd.nextInt(3)), f.pack(sign(), clampExp(f.bias + 1 - ea), mantissa()))
      case _ => (normalNear1(3), normalNear1(3))
    }
  }

  /** a and b whose exact sum (or difference, by sign) sits exactly halfway between neighbours
    * when no normalization shift intervenes: b's lowest set bit weighs half of a's ulp. */
  def addTie(): (Long, Long) = {
    val ea = expIn(f.manWidth + 3, f.expMax - 2)
    val j = 1 + rnd.nextInt(math.min(f.manWidth + 1, ea - 1)) // b's exponent is ea - j
    val sigB = ((rnd.nextLong() & ((1L << n) - 1)) | (1L << f.manWidth)) >>> (j - 1) << (j - 1) | (1L << (j - 1))
    (f.pack(sign(), ea, mantissa()), f.pack(sign(), ea - j, sigB & f.manMask))
  }

  /** a and b whose exact product has exactly manWidth+2 significant bits, the last one set: a tie
    * whenever the product's significand length comes out at manWidth+2. */
  def mulTie(): (Long, Long) = {
    val total = n + 1 + rnd.nextInt(2) // significant bits of the two odd significands together
    val ka = 1 + rnd.nextInt(math.min(n, total - 1))
    val kb = math.min(n, total - ka)
    def oddSig(k: Int): Long = ((rnd.nextLong() & ((1L << (k - 1)) - 1)) | (1L << (k - 1)) | 1L) << (n - k)
    (f.pack(sign(), expIn(f.bias - 6, f.bias + 6), oddSig(ka) & f.manMask),
      f.pack(sign(), expIn(f.bias - 6, f.bias + 6), oddSig(kb) & f.manMask))
  }
}
