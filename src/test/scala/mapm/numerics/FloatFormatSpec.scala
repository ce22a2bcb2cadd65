package mapm.numerics

import mapm.MapmError
import org.scalatest.funsuite.AnyFunSuite

class FloatFormatSpec extends AnyFunSuite {

  test("fp32 encoding equals the JVM's own Float rounding (nearest even) on random doubles") {
    val rnd = new scala.util.Random(7)
    val f = FloatFormat.fp32
    var n = 0
    while (n < 200000) {
      val d = java.lang.Double.longBitsToDouble(rnd.nextLong())
      val fl = d.toFloat
      if (!d.isNaN && !d.isInfinite && !fl.isInfinite && java.lang.Math.abs(fl) >= java.lang.Float.MIN_NORMAL) {
        assert(f.encode(d) == (java.lang.Float.floatToRawIntBits(fl).toLong & 0xffffffffL), s"d=$d")
        n += 1
      }
    }
  }

  test("exhaustive e4m3: every pattern round-trips, midpoints round to even, below min normal flushes") {
    val f = FloatFormat(4, 3)
    val finite = (0L until (1L << f.width)).filter(b => f.isFinite(b) && (f.expField(b) != 0 || f.manField(b) == 0))
    for (b <- finite) assert(f.encode(f.decode(b)) == b || f.decode(b) == 0.0)
    val positives = finite.filter(b => f.sign(b) == 0).map(f.decode).distinct.sorted
    for (Seq(a, b) <- positives.sliding(2) if a > 0) {
      val mid = (a + b) / 2
      val want = if ((f.manField(f.encode(a)) & 1) == 0) a else b
      assert(f.decode(f.encode(mid)) == want, s"midpoint of $a and $b")
      assert(f.decode(f.encode(Math.nextUp(mid))) == b)
      assert(f.decode(f.encode(Math.nextDown(mid))) == a)
    }
    assert(f.encode(f.minNormal * 0.9) == 0L)
    assert(f.encode(-f.minNormal * 0.5) == f.pack(1, 0, 0))
    assert(f.decode(f.encode(f.minNormal * (1 - 1.0 / 64))) == f.minNormal) // rounds up to the smallest normal
  }

  test("NaN, infinity and overflow are rejected with a message") {
    val f = FloatFormat.fp16
    assert(intercept[MapmError](f.encode(Double.NaN, "h")).getMessage.contains("h is NaN"))
    assert(intercept[MapmError](f.encode(Double.PositiveInfinity)).getMessage.contains("infinite"))
    assert(intercept[MapmError](f.encode(70000.0)).getMessage.contains("overflows"))
    assert(f.encode(65519.0) == 0x7bffL) // rounds down to max finite
    assert(f.tryEncode(65520.0).isEmpty) // rounds up past it
  }

  test("presets and parsing") {
    assert(FloatFormat.parse("fp32") == FloatFormat(8, 23))
    assert(FloatFormat.parse("bf16") == FloatFormat(8, 7))
    assert(FloatFormat.parse("5,10") == FloatFormat.fp16)
    assert(FloatFormat.parse("e8m15") == FloatFormat.fp24)
    assert(intercept[MapmError](FloatFormat.parse("12,3")).getMessage.contains("exponent width"))
    assert(intercept[MapmError](FloatFormat.parse("fp8")).getMessage.contains("unknown float format"))
  }
}
