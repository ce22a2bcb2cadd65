package mapm.model

import mapm.numerics._

import mapm.Slow
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
    case Inf(n)    => Inf(n ^ (b.num < 0))
    case Zero      => Zero
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

@Slow
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
        val (p2, c2) = (value(rnd, f, 0, sp), value(rnd, f, -1, sp))
        val out = new Array[Long](3)
        val bits = Seq(k, b, h, p, p2, p, c, c2, c2).map(x => f.encode(x))
        a.shade(bits(0), bits(1), bits(2), bits(3), bits(4), bits(5), bits(6), bits(7), bits(8), out)
        assert(out.toSeq == Seq(got, refColor(f, k, b, h, p2, c2), refColor(f, k, b, h, p, c2)), "shade")
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

  for (f <- Seq(FloatFormat.fp16, FloatFormat(5, 3), FloatFormat.fp32, FloatFormat(4, 2)))
    test(s"cond in $f equals the exact per-operation rounding where |q - p| is within a few ulps of h") {
      val rnd = new scala.util.Random(f.width)
      val a = new RoundedShadeArith(f)
      var inside, outside = 0
      for (_ <- 0 until 20000) {
        val h = value(rnd, f, 1, 2)
        val dx = f.quantize(h * (rnd.nextDouble() - 0.5)); val dy = f.quantize(h * (rnd.nextDouble() - 0.5))
        val dz0 = math.sqrt(math.max(0, h * h - dx * dx - dy * dy))
        val dz = f.tryEncode(dz0).map(b => f.decode(b + rnd.nextInt(7) - 3)).getOrElse(0.0).max(0.0)
        val q = Seq.fill(3)(f.quantize(value(rnd, f, 2, 1)))
        val p = q.zip(Seq(dx, dy, dz)).map { case (c, d) => f.quantize(c - d) }
        if (f.tryEncode(h * h).isDefined) {
          val bits = (q ++ p :+ h).map(x => f.encode(x))
          val want = refCond(f, q, p, h)
          if (want) inside += 1 else outside += 1
          assert(a.cond(bits(0), bits(1), bits(2), bits(3), bits(4), bits(5), bits(6)) == want, s"cond q=$q p=$p h=$h")
        }
      }
      assert(inside > 3000 && outside > 3000)
    }

  for (f <- Seq(FloatFormat.fp16, FloatFormat(5, 3), FloatFormat.fp32, FloatFormat(4, 2), FloatFormat.fp64))
    test(s"condClearBounds in $f: cond is true below lo and false above hi (exact squared distance)") {
      val rnd = new scala.util.Random(f.width + 100)
      val a = new RoundedShadeArith(f)
      var decided = 0
      for (_ <- 0 until 20000) {
        val h = value(rnd, f, 1, 2)
        val scale = h * (0.5 + rnd.nextDouble())
        val q = Seq.fill(3)(f.quantize(value(rnd, f, 2, 1)))
        val p = q.map(c => f.quantize(c - scale * (rnd.nextDouble() - 0.5) * 1.3))
        if (f.tryEncode(h * h).isDefined) {
          val (lo, hi) = a.condClearBounds(f.encode(h))
          assert(lo <= h * h && hi >= h * h && hi - lo <= h * h * (64 * math.pow(2, -f.manWidth) + 1e-11) + 64 * f.minNormal)
          val d2 = q.zip(p).map { case (x, y) => val d = add(of(x), neg(of(y))); mul(d, d) }.reduce(add)
          val want = refCond(f, q, p, h)
          if (less(d2, of(lo))) { assert(want, s"below lo: q=$q p=$p h=$h"); decided += 1 }
          if (less(of(hi), d2)) { assert(!want, s"above hi: q=$q p=$p h=$h"); decided += 1 }
        }
      }
      assert(decided > (if (f.manWidth < 3) 10000 else 15000)) // e4m2's bounds are a factor 2 wide
    }

  test("the default condClearBounds decide nothing") {
    val plain = new ShadeArith {
      def format = FloatFormat.fp32
      def cond(qx: Long, qy: Long, qz: Long, px: Long, py: Long, pz: Long, h: Long) = false
      def color(kernel: Long, brdf: Long, h: Long, power: Long, contrib: Long) = 0L
    }
    assert(plain.condClearBounds(0x3f800000L) == ((Double.NegativeInfinity, Double.PositiveInfinity)))
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

  /** Seeded doubles that probe [[RoundedShadeArith.round]]: raw patterns over binary64's whole
    * range, products of two values of `f`, exact ties between neighbours of `f`, values a few
    * binary64 ulps around the smallest normal and the largest finite value of `f` and its ties there,
    * and the special values. */
  private def roundProbes(f: FloatFormat, rnd: scala.util.Random, n: Int): Seq[Double] = {
    val specials = Seq(0.0, -0.0, Double.MinPositiveValue, -Double.MinPositiveValue, Double.PositiveInfinity,
      Double.NegativeInfinity, Double.NaN, Double.MaxValue, f.minNormal, f.maxFinite)
    val halfUlpMax = math.pow(2, f.maxExp - f.manWidth - 1)
    val edges = for {
      base <- Seq(f.minNormal, f.maxFinite, f.maxFinite + halfUlpMax, f.minNormal * (1 - math.pow(2, -f.manWidth - 2)),
        f.minNormal * (1 - math.pow(2, -f.manWidth - 1)), f.minNormal / 2)
      k <- -8 to 8
      sign <- Seq(1.0, -1.0)
    } yield sign * java.lang.Double.longBitsToDouble(java.lang.Double.doubleToRawLongBits(base) + k)
    val random = Seq.fill(n) {
      rnd.nextInt(4) match {
        case 0 => java.lang.Double.longBitsToDouble(rnd.nextLong())
        case 1 => value(rnd, f, 0, f.maxExp) * value(rnd, f, 0, f.maxExp) * (if (rnd.nextBoolean()) 1 else -1)
        case 2 => // the midpoint of two neighbours of f (exact in binary64): a tie
          val b = f.encode(value(rnd, f, 0, f.maxExp))
          (f.decode(b) + f.decode(b + 1)) / 2
        case _ => value(rnd, f, f.minExp, 3) * (1 + (rnd.nextInt(64) - 32) * math.pow(2, -f.manWidth - 3))
      }
    }
    specials ++ edges ++ random
  }

  for (f <- Seq(FloatFormat.fp32, FloatFormat(6, 23), FloatFormat(4, 23), FloatFormat(8, 15), FloatFormat.fp16, FloatFormat(10, 24)))
    test(s"round in $f (through binary32: ${RoundedShadeArith.roundsViaFloat(f)}) equals roundByBits bit for bit") {
      val a = new RoundedShadeArith(f)
      val rnd = new scala.util.Random(f.width * 7 + f.expWidth)
      var viaFloat = 0
      for (d <- roundProbes(f, rnd, 200000)) {
        val got = a.round(d); val want = a.roundByBits(d)
        assert(java.lang.Double.doubleToRawLongBits(got) == java.lang.Double.doubleToRawLongBits(want) || (got.isNaN && want.isNaN),
          s"round($d) = $got, by bits $want")
        if (math.abs(want) > f.minNormal && math.abs(want) <= f.maxFinite) viaFloat += 1
      }
      assert(viaFloat > 50000)
      // the bit arithmetic itself against the exact rounding of the reference (finite inputs)
      for (d <- roundProbes(f, rnd, 20000) if !d.isNaN && !d.isInfinite) {
        val want = toDouble(round(of(d), f))
        val got = a.roundByBits(d)
        assert(got == want, s"roundByBits($d) = $got, exact $want")
      }
    }

  for (f <- Seq(FloatFormat.fp32, FloatFormat(6, 23), FloatFormat.bf16, FloatFormat.fp16, FloatFormat(10, 12), FloatFormat.fp64))
    test(s"shadeValues in $f equals the decoded shade and the exact reference, for any finite bit patterns") {
      val a = new RoundedShadeArith(f)
      val codec = new FormatBits(f)
      val rnd = new scala.util.Random(f.width * 13 + 5)
      val bits = new Array[Long](3); val values = new Array[Double](3); val want = new Array[Long](3)
      // any finite pattern: exponent fields 0 (zero, or a denormal field that reads as zero) to expMax - 1
      def pattern(): Long = {
        val e = rnd.nextInt(5) match { case 0 => 0; case 1 => 1 + rnd.nextInt(3); case 2 => f.expMax - 1 - rnd.nextInt(3); case _ => rnd.nextInt(f.expMax) }
        f.pack(rnd.nextInt(2), e, rnd.nextLong() & f.manMask)
      }
      def near(center: Int): Long = f.encode(value(rnd, f, center, 4) * (if (rnd.nextInt(8) == 0) -1 else 1))
      for (i <- 0 until 50000) {
        val v = if (i % 2 == 0) Array.fill(9)(pattern()) else Array(near(-2), near(-1), near(2), near(0), near(0), near(1), near(-1), near(-2), near(-1))
        if (f.expField(v(2)) == 0) v(2) = f.encode(1.5) // h is never zero
        if (i % 5 == 0) { v(0) = f.encode(0.125); v(1) = f.encode(0.25); v(2) = f.encode(3.0) } // a repeating prefix
        a.shade(v(0), v(1), v(2), v(3), v(4), v(5), v(6), v(7), v(8), want)
        a.shadeValues(v(0), v(1), v(2), v(3), v(4), v(5), v(6), v(7), v(8), bits, values)
        for (c <- 0 until 3) {
          assert(java.lang.Double.doubleToRawLongBits(values(c)) == java.lang.Double.doubleToRawLongBits(codec.toDouble(want(c))),
            s"channel $c of ${v.map(f.hex).mkString(" ")}: ${values(c)} vs ${codec.toDouble(want(c))}")
          if (f != FloatFormat.fp64) { // binary64 itself rounds its products natively (gradual underflow)
            val ref = refColor(f, f.decode(v(0)), f.decode(v(1)), f.decode(v(2)), f.decode(v(3 + c)), f.decode(v(6 + c)))
            assert(want(c) == ref, s"shade channel $c of ${v.map(f.hex).mkString(" ")}")
          }
        }
      }
    }

  for (f <- Seq(FloatFormat.fp32, FloatFormat(6, 23), FloatFormat.fp16, FloatFormat.fp64))
    test(s"decode in $f (fast fp32 path: ${f == FloatFormat.fp32}) equals FormatBits.toDouble bit for bit on any pattern") {
      val a = new RoundedShadeArith(f)
      val codec = new FormatBits(f)
      val rnd = new scala.util.Random(f.width + 77)
      val edges = for (e <- Seq(0, 1, 2, f.expMax - 2, f.expMax - 1, f.expMax); m <- Seq(0L, 1L, f.manMask, f.manMask - 1); s <- 0 to 1)
        yield f.pack(s, e, m)
      for (b <- edges ++ Seq.fill(200000)(rnd.nextLong() & f.mask)) {
        val got = a.decode(b); val want = codec.toDouble(b)
        assert(java.lang.Double.doubleToRawLongBits(got) == java.lang.Double.doubleToRawLongBits(want),
          s"decode(${f.hex(b)}) = $got, FormatBits $want")
      }
    }
}
