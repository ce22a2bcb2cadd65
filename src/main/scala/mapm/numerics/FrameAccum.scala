package mapm.numerics

/** The frame accumulation of the MAPM coprocessor (docs/coprocessor.md, "Accumulation"): how the
  * hardware adds every passing shader operation's colour into its query's pixel so that the frame
  * buffer is the same bit for bit whatever order the SOs come back in.
  *
  * Each pixel holds one signed fixed-point sum per channel, `accBits` wide, whose least
  * significant bit weighs 2^scale (`scale` is a run-time register, FRAME_SCALE), and a count of
  * the contributions it took, `countBits` wide.
  *
  *  1. A colour channel c (format bits) becomes the integer [[convert]](c) = c * 2^-scale rounded
  *     to nearest, ties to even. Exponent field 0 is zero (the formats flush subnormals). An
  *     infinity or NaN is fault [[FrameAccum.NonFinite]]; a result of magnitude 2^[[limitBits]]
  *     or more is fault [[FrameAccum.Range]]. Both are properties of the one value, never of the
  *     order.
  *  2. The pixel's sums add the converted channels as integers; its count adds one. Integer
  *     addition is associative and commutative, so the sums are those of any order. Because
  *     every term is below 2^limitBits and the count stays below 2^countBits, every partial sum
  *     is below 2^(accBits - 1) in magnitude: the sums never wrap. A contribution that would take
  *     the count to 2^countBits is fault [[FrameAccum.Count]].
  *  3. At the end each sum is rounded once to the format ([[resolve]]): sum * 2^scale to nearest,
  *     ties to even, with the format's conventions (a result below the smallest normal is a zero
  *     of its sign, above the largest finite value infinity); a zero sum is +0. A pixel that took
  *     a faulted contribution resolves to the format's quiet NaN in every channel.
  *
  * The first step is the only rounding before the last: a contribution loses at most half of
  * 2^scale. The host picks `scale` so that its largest contribution fits ([[scaleFor]]).
  */
final case class FrameAccum(format: FloatFormat, accBits: Int, countBits: Int) {
  require(accBits >= 16 && accBits <= 128, s"frame accumulator width must be 16..128 bits, got $accBits")
  require(countBits >= 1 && countBits <= accBits - 8,
    s"frame count width must be 1..${accBits - 8} bits for $accBits-bit sums, got $countBits")

  /** A converted contribution's magnitude is below 2^limitBits. */
  val limitBits: Int = accBits - 1 - countBits

  /** The largest number of contributions one pixel may take. */
  val maxCount: Long = (1L << math.min(countBits, 62)) - 1

  /** c * 2^-scale rounded to nearest even, or the fault that refuses it. */
  def convert(bits: Long, scale: Int): Either[FrameAccum.Fault, BigInt] = {
    val e = format.expField(bits)
    if (e == format.expMax) return Left(FrameAccum.NonFinite)
    if (e == 0) return Right(BigInt(0))
    val sig = BigInt((1L << format.manWidth) | format.manField(bits))
    // c = sig * 2^(e - bias - manWidth); in units of 2^scale: sig * 2^shift.
    val shift = e - format.bias - format.manWidth - scale
    val mag =
      if (shift >= 0) sig << shift
      else {
        val k = -shift
        val q = sig >> k
        val rem = sig - (q << k)
        val half = BigInt(1) << (k - 1)
        if (rem > half || (rem == half && q.testBit(0))) q + 1 else q
      }
    if (mag.bitLength > limitBits) Left(FrameAccum.Range)
    else Right(if (format.sign(bits) == 1) -mag else mag)
  }

  /** sum * 2^scale rounded once to the format (bits). */
  def resolve(sum: BigInt, scale: Int): Long = {
    if (sum == 0) return 0L
    val s = if (sum < 0) 1 else 0
    val mag = sum.abs
    val n = format.manWidth + 1
    val top = mag.bitLength - 1
    // Keep the top n bits, round on the rest.
    val drop = top + 1 - n
    var q =
      if (drop <= 0) mag << -drop
      else {
        val kept = mag >> drop
        val rem = mag - (kept << drop)
        val half = BigInt(1) << (drop - 1)
        if (rem > half || (rem == half && kept.testBit(0))) kept + 1 else kept
      }
    var lsb = drop + scale // exponent of q's least significant bit
    if (q.bitLength > n) { q >>= 1; lsb += 1 }
    val e = lsb + format.manWidth // unbiased exponent of the leading bit
    if (e > format.maxExp) format.pack(s, format.expMax, 0)
    else if (e < format.minExp) format.pack(s, 0, 0)
    else format.pack(s, e + format.bias, q.toLong & format.manMask)
  }

  /** A scale that fits every contribution of magnitude up to `maxAbs` (an upper bound: the
    * largest colour the model's SOs produce, or one the host derives from the photons' powers)
    * with at most one bit of the limit to spare: `maxAbs` converts below 2^(limitBits - 1), and at
    * two less it would be refused. */
  def scaleFor(maxAbs: Double): Int = {
    require(maxAbs >= 0 && !maxAbs.isInfinite && !maxAbs.isNaN, s"the largest contribution must be finite, got $maxAbs")
    if (maxAbs == 0) return FrameAccum.DefaultScale
    // maxAbs < 2^(exponent + 1); rounding may reach 2^(exponent + 1) itself, so leave one bit.
    java.lang.Math.getExponent(maxAbs) + 2 - limitBits
  }
}

object FrameAccum {
  /** Why a contribution is refused (the error-cause bits of docs/coprocessor.md). */
  sealed abstract class Fault(val bit: Int, val reason: String)
  case object NonFinite extends Fault(0, "a colour is infinite or NaN")
  case object Range extends Fault(1, "a colour is too large for the frame scale")
  case object Count extends Fault(2, "a pixel took more contributions than its count holds")
  val Faults: Seq[Fault] = Seq(NonFinite, Range, Count)

  /** The scale when nothing says otherwise: 2^-40, sub-picounit resolution for colours below 2^(limitBits - 40). */
  val DefaultScale: Int = -40

  /** Default widths: 64-bit sums and 24-bit counts up to 32-bit formats; 128-bit sums for wider formats. */
  def default(format: FloatFormat): FrameAccum =
    FrameAccum(format, if (format.width <= 32) 64 else 128, 24)
}

/** A frame's pixels under [[FrameAccum]]: sums, counts and faults, in any order of [[add]]. */
final class FrameSums(val accum: FrameAccum, val pixels: Int, val channels: Int, val scale: Int) {
  private val sums = Array.fill(pixels * channels)(BigInt(0))
  private val counts = new Array[Long](pixels)
  private val bad = new Array[Boolean](pixels)
  private var faultBits = 0

  /** Adds one contribution (one value per channel) to `pixel`. */
  def add(pixel: Int, colour: Seq[Long]): Unit = {
    require(colour.length == channels, s"a contribution has $channels channels, got ${colour.length}")
    val conv = colour.map(accum.convert(_, scale))
    val fault = conv.collectFirst { case Left(f) => f }
      .orElse(if (counts(pixel) == accum.maxCount) Some(FrameAccum.Count) else None)
    fault match {
      case Some(f) => bad(pixel) = true; faultBits |= 1 << f.bit
      case None =>
        counts(pixel) += 1
        for ((Right(v), c) <- conv.zipWithIndex) sums(pixel * channels + c) += v
    }
  }

  /** The faults seen, one bit each ([[FrameAccum.Fault.bit]]). */
  def faults: Int = faultBits
  def count(pixel: Int): Long = counts(pixel)
  def sum(pixel: Int, channel: Int): BigInt = sums(pixel * channels + channel)

  /** The pixel's channels as the frame buffer holds them (format bits). */
  def resolve(pixel: Int): Seq[Long] =
    if (bad(pixel)) Seq.fill(channels)(accum.format.quietNaN)
    else (0 until channels).map(c => accum.resolve(sums(pixel * channels + c), scale))
}
