package mapm.model

import mapm.MapmError
import org.scalatest.funsuite.AnyFunSuite

/** Exact reference for "each operation rounded to the format": rationals in BigInt, one rounding
  * (nearest even, flush below the smallest normal, infinity above the largest finite) per step. */
object ExactRounding {
  /** Zero, a signed infinity, or a finite non-zero rational num/den (den > 0). */
  sealed trait V
  case object Zero extends V
  final case class Inf(neg: Boolean) extends V
  final case class Rat(num: BigInt, den: BigInt) extends V

  def of(d: Double): V =
    if (d == 0) Zero
    else {
      val b = new java.math.BigDecimal(d)
      if (b.scale <= 0) Rat(BigInt(b.unscaledValue) * BigInt(10).pow(-b.scale), 1)
      else Rat(BigInt(b.unscaledValue), BigInt(10).pow(b.scale))
    }

  def round(v: V, f: FloatFormat): V = v match {
    case Rat(num, den) =>
      val a = num.abs
      var e = a.bitLength - den.bitLength
      def ge(e: Int) = if (e >= 0) a >= (den << e) else (a << -e) >= den
      while (!ge(e)) e -= 1
      while (ge(e + 1)) e += 1
      val m = f.manWidth
      val sh = m - e
      val (aa, dd) = if (sh >= 0) (a << sh, den) else (a, den << -sh)
      var (q, r) = aa /% dd
      if (2 * r > dd || (2 * r == dd && q.testBit(0))) q += 1
      if (q.bitLength > m + 1) { q >>= 1; e += 1 }
      if (e < f.minExp) Zero
      else if (e > f.maxExp) Inf(num < 0)
      else {
        val n = if (num < 0) -q else q
        if (e - m >= 0) Rat(n << (e - m), 1) else Rat(n, BigInt(1) << (m - e))
      }
    case other => other
  }

  private def sgn(v: V): Int = v match { case Zero => 0; case Inf(n) => if (n) -1 else 1; case Rat(n, _) => n.signum }

  def mul(a: V, b: V): V = (a, b) match {
    case (Zero, _) | (_, Zero)      => Zero // no 0 * inf arises in the tested chains
    case (Rat(n1, d1), Rat(n2, d2)) => Rat(n1 * n2, d1 * d2)
    case _                          => Inf(sgn(a) * sgn(b) < 0)
  }
  def div(a: V, b: Rat): V = a match {
    case Rat(n, d) => if (b.num < 0) Rat(-n * b.den, d * -b.num) else Rat(n * b.den, d * b.num)
    case other     => other
  }
  def add(a: V, b: V): V = (a, b) match {
    case (Zero, x)                  => x
    case (x, Zero)                  => x
    case (Rat(n1, d1), Rat(n2, d2)) => val n = n1 * d2 + n2 * d1; if (n == 0) Zero else Rat(n, d1 * d2)
    case (i: Inf, _)                => i
    case (_, i: Inf)                => i
  }
  def neg(a: V): V = a match { case Zero => Zero; case Inf(n) => Inf(!n); case Rat(n, d) => Rat(-n, d) }
  def less(a: V, b: V): Boolean = (a, b) match {
    case (Rat(n1, d1), Rat(n2, d2)) => n1 * d2 < n2 * d1
    case _                          => sgn(a) < sgn(b) || (sgn(a) == sgn(b) && ((a, b) match {
      case (Inf(_), Inf(_)) | (Zero, Zero) => false
      case (Inf(n), _)                     => n
      case (_, Inf(n))                     => !n
      case _                               => false
    }))
  }
  def toDouble(v: V): Double = v match {
    case Zero => 0.0; case Inf(n) => if (n) Double.NegativeInfinity else Double.PositiveInfinity
    case Rat(n, d) => new java.math.BigDecimal(n.bigInteger).divide(new java.math.BigDecimal(d.bigInteger)).doubleValue // exact: d is a power of two
  }
}

class ShadingSpec extends AnyFunSuite {
  import ExactRounding._

  private def refColor(f: FloatFormat, k: Double, b: Double, h: Double, p: Double, c: Double): Long = {
    if (k == 0 || b == 0 || p == 0 || c == 0) return 0L
    def r(v: V) = round(v, f)
    val t = r(mul(r(mul(r(div(r(mul(of(k), of(b))), of(h).asInstanceOf[Rat])), of(p))), of(c)))
    t match {
      case Zero   => 0L
      case Inf(n) => f.pack(if (n) 1 else 0, f.expMax - 1, f.manMask)
      case v      => f.encode(toDouble(v))
    }
  }

  private def refCond(f: FloatFormat, q: Seq[Double], p: Seq[Double], h: Double): Boolean = {
    def r(v: V) = round(v, f)
    val d = q.zip(p).map { case (a, b) => r(add(of(a), neg(of(b)))) }
    val sq = d.map(x => r(mul(x, x)))
    val d2 = r(add(r(add(sq(0), sq(1))), sq(2)))
    less(d2, r(mul(of(h), of(h))))
  }

  /** A random positive value of `f` with exponent in [-span, span] around 2^center. */
  private def value(rnd: scala.util.Random, f: FloatFormat, center: Int, span: Int): Double = {
    val e = (center + rnd.nextInt(2 * span + 1) - span).max(f.minExp).min(f.maxExp)
    val man = rnd.nextInt(4) match {
      case 0 => 0L; case 1 => f.manMask; case _ => rnd.nextLong() & f.manMask
    }
    f.decode(f.pack(0, e + f.bias, man))
  }

  for (f <- Seq(FloatFormat.fp16, FloatFormat.bf16, FloatFormat(5, 4), FloatFormat(6, 24), FloatFormat.fp32, FloatFormat(10, 12)))
    test(s"color and cond in $f equal the exact per-operation rounding (including overflow and underflow)") {
      val rnd = new scala.util.Random(f.width * 31 + f.expWidth)
      val a = new RoundedShadeArith(f)
      val span = (f.maxExp * 2 / 3).max(2)
      for (i <- 0 until 20000) {
        val wide = i % 3 == 0
        val sp = if (wide) span else 3
        val k = value(rnd, f, 0, sp); val b = if (i % 7 == 0) 1.0 else value(rnd, f, -1, sp)
        val h = value(rnd, f, 0, sp); val p = value(rnd, f, 0, sp)
        val c = if (i % 11 == 0) 0.0 else value(rnd, f, -1, sp)
        val got = a.color(f.encode(k), f.encode(b), f.encode(h), f.encode(p), f.encode(c))
        assert(got == refColor(f, k, b, h, p, c), s"color k=$k b=$b h=$h p=$p c=$c")
        val q = Seq.fill(3)(value(rnd, f, 2, if (wide) span / 2 else 2) * (if (rnd.nextBoolean()) 1 else -1))
        val ph = q.map(x => if (rnd.nextInt(4) == 0) x else x + f.quantize(value(rnd, f, 1, 3) * (if (rnd.nextBoolean()) 1 else -1)))
          .map(x => f.tryEncode(x).map(f.decode).getOrElse(0.0))
        val hh = value(rnd, f, 2, 2)
        if (f.tryEncode(hh * hh).isDefined) {
          val bits = (q ++ ph :+ hh).map(x => f.encode(x))
          assert(a.cond(bits(0), bits(1), bits(2), bits(3), bits(4), bits(5), bits(6)) == refCond(f, q, ph, hh), s"cond q=$q p=$ph h=$hh")
        }
      }
    }

  test("fp32 color equals the JVM's float arithmetic in the normal range") {
    val f = FloatFormat.fp32
    val a = new RoundedShadeArith(f)
    val rnd = new scala.util.Random(3)
    for (_ <- 0 until 100000) {
      val v = Array.fill(5)(value(rnd, f, 0, 20).toFloat)
      val want = (((v(0) * v(1)) / v(2)) * v(3)) * v(4)
      val got = a.color(f.encode(v(0)), f.encode(v(1)), f.encode(v(2)), f.encode(v(3)), f.encode(v(4)))
      assert(got == (java.lang.Float.floatToRawIntBits(want).toLong & 0xffffffffL))
    }
  }

  test("the float64 path is plain double arithmetic") {
    val a = ShadeArith.float64
    val f = FloatFormat.fp64
    val rnd = new scala.util.Random(4)
    for (_ <- 0 until 20000) {
      val v = Array.fill(5)(rnd.nextDouble() * 10 + 1e-3)
      val got = f.decode(a.color(f.encode(v(0)), f.encode(v(1)), f.encode(v(2)), f.encode(v(3)), f.encode(v(4))))
      assert(got == (((v(0) * v(1)) / v(2)) * v(3)) * v(4))
      val q = Array.fill(3)(rnd.nextDouble() * 100); val p = Array.fill(3)(rnd.nextDouble() * 100); val h = rnd.nextDouble() * 60
      val d = q.zip(p).map { case (x, y) => x - y }
      val b = (q ++ p :+ h).map(x => f.encode(x))
      assert(a.cond(b(0), b(1), b(2), b(3), b(4), b(5), b(6)) == (d(0) * d(0) + d(1) * d(1) + d(2) * d(2) < h * h))
    }
  }

  test("formats the rounded path cannot do exactly are rejected") {
    for (f <- Seq(FloatFormat(8, 25), FloatFormat(11, 24), FloatFormat(11, 40)))
      assert(intercept[MapmError](ShadeArith.rounded(f)).getMessage.contains("mantissa width <= 24"))
    ShadeArith.rounded(FloatFormat(10, 24))
    ShadeArith.rounded(FloatFormat.fp64)
  }

  test("zero factors give +0, overflow saturates, and the kernel is the constant disc kernel") {
    val f = FloatFormat.fp16
    val a = new RoundedShadeArith(f)
    val one = f.encode(1.0)
    assert(a.color(one, one, one, one, f.encode(0.0)) == 0L)
    assert(a.color(one, f.encode(-0.0), one, one, one) == 0L)
    assert(a.color(f.encode(60000.0), f.encode(60000.0), one, one, one) == 0x7bffL)
    assert(a.color(f.encode(1e-4), f.encode(1e-4), one, one, one) == 0L)
    for (h <- Seq(0.5, 3.0, 100.0))
      assert(math.abs(Shading.kernel(h) / h * Shading.brdf * math.Pi * math.Pi * h * h - 1) < 1e-15)
  }
}
