package mapm.numerics

import java.math.BigInteger
import org.scalatest.funsuite.AnyFunSuite

/** [[FrameAccum]] against exact rationals ([[ExactFloat]]): conversion and the final rounding
  * exhaustively at small widths, the order independence and the exactness of a frame at full
  * width with seeded random contributions, and every fault. */
class FrameAccumSpec extends AnyFunSuite {
  private val e4m3 = FloatFormat(4, 3)

  /** value * 2^-scale rounded to nearest even, by exact division (the reference). */
  private def refConvert(f: FloatFormat, bits: Long, scale: Int): Option[BigInt] = ExactFloat.decode(f, bits) match {
    case ExactFloat.Num(num, den, _) =>
      val (n, d) = if (scale <= 0) (num.shiftLeft(-scale), den) else (num, den.shiftLeft(scale))
      val qr = n.abs.divideAndRemainder(d)
      val c = qr(1).shiftLeft(1).compareTo(d)
      val q = if (c > 0 || (c == 0 && qr(0).testBit(0))) qr(0).add(BigInteger.ONE) else qr(0)
      Some(BigInt(if (n.signum < 0) q.negate else q))
    case _ => None
  }

  test("convert: every e4m3 pattern at scales -12..4 is the exact value rounded to nearest even, or the fault it must be") {
    val fa = FrameAccum(e4m3, 16, 4) // limit 2^11
    assert(fa.limitBits == 11)
    for (bits <- 0L until 256L; scale <- -12 to 4) {
      val got = fa.convert(bits, scale)
      refConvert(e4m3, bits, scale) match {
        case None => assert(got == Left(FrameAccum.NonFinite), s"bits $bits")
        case Some(v) if v.abs >= (BigInt(1) << 11) => assert(got == Left(FrameAccum.Range), s"bits $bits scale $scale")
        case Some(v) => assert(got == Right(v), s"bits $bits scale $scale")
      }
    }
  }

  test("resolve: every sum in -2^12..2^12 at scales -14..6 rounds once to the nearest e4m3 (flush, overflow, +0)") {
    val fa = FrameAccum(e4m3, 16, 4)
    for (sum <- -(1 << 12) to (1 << 12); scale <- -14 to 6) {
      val want =
        if (sum == 0) 0L
        else {
          val m = BigInteger.valueOf(math.abs(sum.toLong))
          val (n, d) = if (scale >= 0) (m.shiftLeft(scale), BigInteger.ONE) else (m, BigInteger.ONE.shiftLeft(-scale))
          ExactFloat.round(e4m3, sum < 0, n, d)
        }
      assert(fa.resolve(BigInt(sum), scale) == want, s"sum $sum scale $scale")
    }
  }

  test("fp32 frame: any order gives the same pixels, and where no contribution rounds they are the exact sum rounded once") {
    val f = FloatFormat.fp32
    val fa = FrameAccum.default(f)
    val rnd = new scala.util.Random(36)
    // Colours in [2^-12, 1): at scale -38 every fp32 value there is a whole number of units (its
    // last bit weighs 2^-35 or more), and below 2^38 of them.
    def colour(): Long = f.pack(if (rnd.nextInt(8) == 0) 1 else 0, f.bias - 12 + rnd.nextInt(12), rnd.nextLong() & f.manMask)
    val pixels = 7
    val adds = Seq.fill(3000)((rnd.nextInt(pixels), Seq.fill(3)(colour())))
    val scale = fa.scaleFor(0.999)
    assert(scale == -38 && fa.limitBits == 39)
    def frame(order: Seq[(Int, Seq[Long])], sc: Int) = {
      val s = new FrameSums(fa, pixels, 3, sc)
      order.foreach { case (p, c) => s.add(p, c) }
      assert(s.faults == 0)
      (0 until pixels).map(s.resolve)
    }
    val ref = frame(adds, scale)
    for (seed <- 1 to 5) assert(frame(new scala.util.Random(seed).shuffle(adds), scale) == ref)
    for (p <- 0 until pixels; ch <- 0 until 3) {
      // The exact rational sum, rounded once by the reference.
      val den = BigInteger.ONE.shiftLeft(200)
      val num = adds.filter(_._1 == p).map(a => ExactFloat.decode(f, a._2(ch)) match {
        case ExactFloat.Num(n, d, _) => n.multiply(den).divide(d)
        case v => fail(s"unexpected $v")
      }).foldLeft(BigInteger.ZERO)(_ add _)
      val want = if (num.signum == 0) 0L else ExactFloat.round(f, num.signum < 0, num.abs, den)
      assert(ref(p)(ch) == want, s"pixel $p channel $ch")
    }
    // A coarser scale rounds each contribution, and still gives one frame for every order.
    val coarse = frame(adds, -20)
    for (seed <- 1 to 3) assert(frame(new scala.util.Random(seed).shuffle(adds), -20) == coarse)
  }

  test("faults: NaN and infinity, a colour beyond the scale, a count that overflows; the pixel reads NaN, the others are kept") {
    val f = FloatFormat.fp32
    val fa = FrameAccum(f, 16, 2) // limit 2^13, at most 3 contributions a pixel
    val one = f.encode(1.0)
    val s = new FrameSums(fa, 4, 3, -4) // 1.0 = 16 units
    s.add(0, Seq(one, f.quietNaN, one))
    s.add(1, Seq(one, one, f.encode(1024.0))) // 16384 units >= 2^13
    for (_ <- 1 to 4) s.add(2, Seq(one, one, one))
    s.add(3, Seq(one, f.posInf, one))
    s.add(3, Seq(one, one, one))
    assert(s.faults == 7)
    for (p <- 0 to 3) assert(s.resolve(p) == Seq.fill(3)(f.quietNaN), s"pixel $p")
    val ok = new FrameSums(fa, 1, 3, -4)
    for (_ <- 1 to 3) ok.add(0, Seq(one, one, f.encode(-0.5)))
    assert(ok.faults == 0 && ok.count(0) == 3)
    assert(ok.resolve(0) == Seq(f.encode(3.0), f.encode(3.0), f.encode(-1.5)))
    assert(FrameAccum.Faults.map(_.bit) == Seq(0, 1, 2))
  }

  test("scaleFor fits the largest contribution, and two steps finer would refuse it") {
    val f = FloatFormat.fp32
    val fa = FrameAccum.default(f)
    val rnd = new scala.util.Random(5)
    for (_ <- 1 to 2000) {
      val bits = f.pack(0, 1 + rnd.nextInt(f.expMax - 1), rnd.nextLong() & f.manMask)
      val v = f.decode(bits)
      val s = fa.scaleFor(v)
      assert(fa.convert(bits, s).exists(_.bitLength <= fa.limitBits - 1), s"$v at $s")
      assert(fa.convert(bits, s - 2) == Left(FrameAccum.Range), s"$v at ${s - 2}")
    }
    assert(fa.scaleFor(0.0) == FrameAccum.DefaultScale)
    assertThrows[IllegalArgumentException](fa.scaleFor(Double.PositiveInfinity))
    assertThrows[IllegalArgumentException](FrameAccum(f, 12, 4))
    assertThrows[IllegalArgumentException](FrameAccum(f, 64, 60))
  }
}
