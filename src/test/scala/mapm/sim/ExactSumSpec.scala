package mapm.sim

import java.nio.file.{Files, Path, Paths}

import mapm.numerics.FloatFormat
import org.scalatest.funsuite.AnyFunSuite
import scala.sys.process._

/** [[ExactSum]] over every format up to 64 bits wide (fp64 included: significands of 53 bits that
  * span three 32-bit limbs), checked against an independent reference: the sum of the decoded
  * values in BigInt, and its own rounding to the nearest double (a binary search over the doubles'
  * bit patterns with exact comparisons, not [[ExactSum.round]]'s algorithm, nor
  * java.math.BigDecimal.doubleValue, whose Javadoc only calls it "similar to" a narrowing
  * conversion). The harness's C++ twin, tools/harness/accum.h, compiled with g++ into a small
  * driver, must give the same doubles bit for bit. */
class ExactSumSpec extends AnyFunSuite {
  private val formats = Seq(FloatFormat.fp64, FloatFormat(10, 40), FloatFormat.fp32, FloatFormat.fp16)

  // ---- the reference ----

  private def signBit(f: FloatFormat): Long = 1L << (f.expWidth + f.manWidth)
  private def expAllOnes(f: FloatFormat): Long = (1L << f.expWidth) - 1

  /** Format bits from sign, exponent field and fraction. */
  private def bitsOf(f: FloatFormat, neg: Boolean, e: Long, m: Long): Long =
    (if (neg) signBit(f) else 0L) | (e << f.manWidth) | (m & ((1L << f.manWidth) - 1))

  /** The value of finite format bits as a BigInt count of 2^(1 - bias - manWidth), the smallest
    * normal's ulp: (2^m + M) * 2^(E - 1), and 0 for exponent field 0 (flushed subnormals). */
  private def refUnits(f: FloatFormat, bits: Long): BigInt = {
    val e = (bits >>> f.manWidth) & expAllOnes(f)
    assert(e != expAllOnes(f))
    if (e == 0) BigInt(0)
    else {
      val v = ((BigInt(1) << f.manWidth) + BigInt(bits & ((1L << f.manWidth) - 1))) << (e - 1).toInt
      if ((bits & signBit(f)) != 0) -v else v
    }
  }
  private def refUnitExp(f: FloatFormat): Int = 1 - ((1 << (f.expWidth - 1)) - 1) - f.manWidth

  private def isNaNOrInf(f: FloatFormat, bits: Long): Boolean = ((bits >>> f.manWidth) & expAllOnes(f)) == expAllOnes(f)

  /** The reference sum of `vals`: None when one is infinite or NaN. */
  private def refSum(f: FloatFormat, vals: Seq[Long]): Option[BigInt] =
    if (vals.exists(isNaNOrInf(f, _))) None else Some(vals.map(refUnits(f, _)).sum)

  /** A finite double's exact value in units of 2^-1074 (every double is a whole number of them). */
  private def doubleUnits(raw: Long): BigInt = {
    val e = (raw >>> 52) & 0x7ff; val m = raw & ((1L << 52) - 1)
    if (e == 0) BigInt(m) else ((BigInt(1) << 52) + m) << (e - 1).toInt
  }
  private val maxRaw = java.lang.Double.doubleToRawLongBits(Double.MaxValue)
  /** The least value that rounds to infinity: halfway from the largest double to 2^1024 (a tie
    * rounds to infinity: the largest double's significand is odd). */
  private val overflow = doubleUnits(maxRaw) + (BigInt(1) << (970 + 1074))

  /** v * 2^unitExp rounded to the nearest double, ties to the even significand; +0.0 for zero. */
  private def nearest(v: BigInt, unitExp: Int): Double = {
    // compared in units of 2^base, of which v's unit and every double are whole numbers
    val base = math.min(unitExp, -1074)
    def at(raw: Long): BigInt = doubleUnits(raw) << (-1074 - base)
    val x = v.abs << (unitExp - base)
    val mag =
      if (x >= (overflow << (-1074 - base))) Double.PositiveInfinity
      else {
        // largest finite bit pattern whose value is at most x (values grow with the pattern)
        var (lo, hi) = (0L, maxRaw)
        while (lo < hi) { val mid = lo + (hi - lo + 1) / 2; if (at(mid) <= x) lo = mid else hi = mid - 1 }
        val raw =
          if (lo == maxRaw) lo
          else {
            val (below, above) = (x - at(lo), at(lo + 1) - x)
            if (below < above || (below == above && (lo & 1) == 0)) lo else lo + 1
          }
        java.lang.Double.longBitsToDouble(raw)
      }
    if (v.signum < 0) -mag else mag
  }

  private def raw(d: Double): Long = java.lang.Double.doubleToRawLongBits(d)
  private def same(a: Double, b: Double): Boolean = raw(a) == raw(b)

  // ---- values ----

  /** Random bits with exponent field in [lo, hi] (1 <= lo <= hi < all ones), negative with
    * probability `neg`, and one in ten with exponent field 0 and a random fraction (a subnormal,
    * counted as zero). */
  private def randomBits(f: FloatFormat, rnd: scala.util.Random, lo: Int, hi: Int, neg: Double): Long = {
    val e = if (rnd.nextInt(10) == 0) 0 else lo + rnd.nextInt(hi - lo + 1)
    bitsOf(f, rnd.nextDouble() < neg, e.toLong, rnd.nextLong())
  }

  /** Values for one sum: kind 0 wide exponents, positive; 1 wide, signed; 2 a narrow exponent
    * window, signed (cancellation, carries and ties); 3 values and their negations (exactly zero);
    * 4 the largest and smallest normal values among others; 5 like 1 with an infinity or NaN. */
  private def randomCase(f: FloatFormat, rnd: scala.util.Random, kind: Int, maxN: Int = 150): Seq[Long] = {
    val top = (expAllOnes(f) - 1).toInt
    val maxNormal = bitsOf(f, neg = false, top.toLong, -1L)
    val minNormal = bitsOf(f, neg = false, 1, 0)
    val n = 1 + rnd.nextInt(maxN)
    kind match {
      case 0 => Seq.fill(n)(randomBits(f, rnd, 1, top, 0.0))
      case 1 => Seq.fill(n)(randomBits(f, rnd, 1, top, 0.5))
      case 2 =>
        val lo = 1 + rnd.nextInt(top); val hi = math.min(top, lo + rnd.nextInt(4))
        Seq.fill(n)(randomBits(f, rnd, lo, hi, 0.5))
      case 3 =>
        val v = Seq.fill(n)(randomBits(f, rnd, 1, top, 0.5))
        rnd.shuffle(v ++ v.map(_ ^ signBit(f)))
      case 4 =>
        rnd.shuffle(Seq.fill(n)(randomBits(f, rnd, 1, top, 0.5)) ++
          Seq.fill(1 + rnd.nextInt(4))(if (rnd.nextBoolean()) maxNormal else maxNormal ^ signBit(f)) ++
          Seq.fill(1 + rnd.nextInt(4))(if (rnd.nextBoolean()) minNormal else minNormal ^ signBit(f)))
      case _ =>
        val special = bitsOf(f, rnd.nextBoolean(), expAllOnes(f), if (rnd.nextBoolean()) 0L else rnd.nextLong() | 1L)
        rnd.shuffle(special +: Seq.fill(n)(randomBits(f, rnd, 1, top, 0.5)))
    }
  }

  /** fp64 sums whose rounding is delicate: ties, sticky bits far below the round bit, overflow to
    * infinity, results in the doubles' subnormal range, cancellation, flushed subnormals. */
  private val fp64Cases: Seq[(String, Seq[Long], Double)] = {
    def d(x: Double): Long = raw(x)
    val minN = java.lang.Double.MIN_NORMAL
    Seq(
      ("1 + 2^-53 (tie, to even)", Seq(d(1.0), d(math.pow(2, -53))), 1.0),
      ("1 + 3 * 2^-53 (tie, up to even)", Seq(d(1.0), d(3 * math.pow(2, -53))), 1.0 + math.pow(2, -51)),
      ("1 + 2^-53 + 2^-1000 (sticky far below)", Seq(d(math.pow(2, -1000)), d(math.pow(2, -53)), d(1.0)), 1.0 + math.pow(2, -52)),
      ("1 + 2^-53 + smallest normal (sticky 970 bits below)", Seq(d(1.0), d(minN), d(math.pow(2, -53))), 1.0 + math.pow(2, -52)),
      ("-(1 + 2^-53)", Seq(d(-1.0), d(-math.pow(2, -53))), -1.0),
      ("max + max (overflow)", Seq(d(Double.MaxValue), d(Double.MaxValue)), Double.PositiveInfinity),
      ("-max - max (overflow)", Seq(d(-Double.MaxValue), d(-Double.MaxValue)), Double.NegativeInfinity),
      ("max + 2^970 (tie at the overflow threshold)", Seq(d(Double.MaxValue), d(math.pow(2, 970))), Double.PositiveInfinity),
      ("max + 2^969", Seq(d(Double.MaxValue), d(math.pow(2, 969))), Double.MaxValue),
      ("max + smallest normal", Seq(d(minN), d(Double.MaxValue)), Double.MaxValue),
      ("smallest normal - next (a subnormal double)", Seq(d(minN), d(-Math.nextUp(minN))), -Double.MinPositiveValue),
      ("next after smallest normal - smallest normal", Seq(d(Math.nextUp(minN)), d(-minN)), Double.MinPositiveValue),
      ("1.5 * 2^-1022 - 2^-1022 (a subnormal double)", Seq(d(1.5 * minN), d(-minN)), minN / 2),
      ("2^-1021 - ulp - 2^-1022 (the largest subnormal double)", Seq(d(-minN), d(Math.nextDown(2 * minN))), Math.nextDown(minN)),
      ("2^1023 + 2^-1022 - 2^1023 (huge parts cancel)", Seq(d(math.pow(2, 1023)), d(minN), d(-math.pow(2, 1023))), minN),
      ("x - x", Seq(d(math.Pi), d(-math.Pi)), 0.0),
      ("a subnormal counts as zero", Seq(0x000fffffffffffffL, d(1.0), 0x8000000000000001L), 1.0),
      ("infinity", Seq(d(1.0), d(Double.PositiveInfinity)), Double.NaN),
      ("NaN", Seq(d(Double.NaN), d(1.0)), Double.NaN)
    )
  }

  /** Sums around ties of 2^k (k < 40) at every offset of the round and sticky bits from the
    * limbs' edges: 2^k + 2^(k-53), + 2^(k-52) (an odd significand) or not, + 2^(k-53-j) for
    * j = 1 to 70 (a sticky bit) or not, negated for odd k + j; for formats reaching 2^-123. */
  private def roundingCases(f: FloatFormat): Seq[Seq[Long]] = {
    require(f.minExp <= -123)
    def pow2(p: Int): Long = bitsOf(f, neg = false, (p + f.bias).toLong, 0)
    for (k <- 0 until 40; odd <- Seq(false, true); j <- 0 to 70) yield {
      val v = Seq(pow2(k), pow2(k - 53)) ++ (if (odd) Seq(pow2(k - 52)) else Nil) ++ (if (j > 0) Seq(pow2(k - 53 - j)) else Nil)
      if ((k + j) % 2 == 1) v.map(_ ^ signBit(f)) else v
    }
  }

  /** `vals` summed in a fresh ExactSum of one sum. */
  private def sumOf(f: FloatFormat, vals: Seq[Long]): ExactSum = {
    val s = new ExactSum(f, 1); vals.foreach(s.add(0, _)); s
  }

  /** Checks one sum of `vals` in three orders, in sums 0..2 of four (3 stays empty). */
  private def check(f: FloatFormat, vals: Seq[Long], rnd: scala.util.Random, what: => String): Unit = {
    val s = new ExactSum(f, 4)
    val orders = Seq(vals, vals.reverse, rnd.shuffle(vals))
    // interleaved, so that a stray write into a neighbouring sum would show
    for (k <- vals.indices; j <- 0 until 3) s.add(j, orders(j)(k))
    assert(s.unitExp == refUnitExp(f) && s.unitExp == f.minExp - f.manWidth, what)
    val ref = refSum(f, vals)
    val want = ref.fold(Double.NaN)(nearest(_, refUnitExp(f)))
    for (j <- 0 until 3) {
      assert(s.exact(j) == ref, s"$what: sum in order $j")
      val d = s.toDouble(j)
      if (ref.isEmpty) assert(d.isNaN, what)
      else assert(same(d, want), s"$what: order $j gives $d, the nearest double is $want")
    }
    assert(s.exact(3).contains(BigInt(0)) && same(s.toDouble(3), 0.0), what)
  }

  // ---- the tests ----

  test("the reference rounding: every double to itself, midpoints to even, overflow to infinity") {
    val rnd = new scala.util.Random(7)
    for (_ <- 0 until 2000) {
      val r = ((rnd.nextLong() >>> 1) % (maxRaw - 2)) & ~1L // positive, finite with the next two; even
      val x = java.lang.Double.longBitsToDouble(r)
      assert(same(nearest(doubleUnits(r), -1074), x))
      assert(same(nearest(-doubleUnits(r + 1), -1074), -java.lang.Double.longBitsToDouble(r + 1)))
      // halfway from x (even) to the next double rounds to x; from the next (odd) up: to the one after
      assert(same(nearest(doubleUnits(r) + doubleUnits(r + 1), -1075), x))
      assert(same(nearest(doubleUnits(r + 1) + doubleUnits(r + 2), -1075), java.lang.Double.longBitsToDouble(r + 2)))
      assert(same(nearest(doubleUnits(r) * 2 + 1, -1075), x))
    }
    assert(same(nearest(overflow, -1074), Double.PositiveInfinity) && same(nearest(overflow - 1, -1074), Double.MaxValue))
    assert(same(nearest(0, 0), 0.0) && same(nearest(1, -1074), Double.MinPositiveValue))
  }

  for (f <- formats)
    test(s"$f: exact in any order and rounded once to the nearest double, against a BigInt reference") {
      val rnd = new scala.util.Random(1000 + f.width)
      for (trial <- 0 until 180) check(f, randomCase(f, rnd, trial % 6), rnd, s"$f trial $trial")
    }

  test("fp64: ties, far sticky bits, overflow, subnormal doubles, cancellation, flushed subnormals, NaN") {
    val f = FloatFormat.fp64
    val rnd = new scala.util.Random(3)
    for ((what, vals, want) <- fp64Cases) {
      check(f, vals, rnd, what)
      assert(same(sumOf(f, vals).toDouble(0), want), s"$what: ${sumOf(f, vals).toDouble(0)} vs $want")
    }
  }

  for (f <- formats.take(3))
    test(s"$f: ties and sticky bits at every offset from the limbs' edges") {
      val rnd = new scala.util.Random(5)
      for (vals <- roundingCases(f)) check(f, vals, rnd, s"$f: ${vals.map(_.toHexString)}")
    }

  test("every format e2..e11 x m1..m52: exact and nearest") {
    val rnd = new scala.util.Random(11)
    for (ew <- 2 to 11; mw <- 1 to 52) {
      val f = FloatFormat(ew, mw)
      for (kind <- 0 until 6) check(f, randomCase(f, rnd, kind, maxN = 20), rnd, s"$f kind $kind")
    }
  }

  // ---- the C++ twin ----

  private val dir = Paths.get("target/exactsum-test")

  private lazy val gppPresent: Boolean = mapm.testutil.HostTools.onPath("g++")

  /** Reads "sum bits" lines (bits in hex) from stdin into `count` sums of format (ew, mw), then
    * prints each sum's double as the hex of its raw bits. */
  private val driver =
    """#include <cinttypes>
      |#include <cstdio>
      |#include <cstdlib>
      |#include <cstring>
      |#include "accum.h"
      |int main(int argc, char** argv) {
      |  if (argc != 4) return 2;
      |  const size_t count = strtoull(argv[3], nullptr, 10);
      |  ExactAccumulators acc(ExactFormat(atoi(argv[1]), atoi(argv[2])), count);
      |  size_t i;
      |  uint64_t bits;
      |  while (scanf("%zu %" SCNx64, &i, &bits) == 2) acc.add(i, bits);
      |  for (size_t k = 0; k < count; k++) {
      |    const double d = acc.toDouble(k);
      |    uint64_t r;
      |    memcpy(&r, &d, sizeof r);
      |    printf("%016" PRIx64 "\n", r);
      |  }
      |  return 0;
      |}
      |""".stripMargin

  private lazy val exe: Path =
    mapm.testutil.HostTools.gpp(dir, "accum_driver", driver, Seq(Paths.get("tools/harness").toAbsolutePath), Seq("-O2", "-Wextra"))

  for (f <- formats)
    test(s"$f: tools/harness/accum.h (g++) gives the doubles of ExactSum, bit for bit") {
      assume(gppPresent, "g++ is not on PATH: this test compiles tools/harness/accum.h with it")
      val rnd = new scala.util.Random(2000 + f.width)
      val cases: IndexedSeq[Seq[Long]] =
        (0 until 300).map(k => randomCase(f, rnd, k % 6)) ++ (if (f == FloatFormat.fp64) fp64Cases.map(_._2) else Nil) ++
          (if (f.minExp <= -123) roundingCases(f) else Nil)
      // the C++ side adds every sum's values interleaved in a random order; the Scala side in turn
      val lines = rnd.shuffle(cases.indices.flatMap(i => cases(i).map(b => f"$i%d ${b & f.mask}%x")))
      Files.createDirectories(dir)
      val in = dir.resolve(s"${f.name}.in")
      Files.write(in, lines.mkString("", "\n", "\n").getBytes("UTF-8"))
      val printed = (Seq(exe.toString, f.expWidth.toString, f.manWidth.toString, cases.size.toString) #< in.toFile).!!.linesIterator.toIndexedSeq
      assert(printed.size == cases.size)
      val s = new ExactSum(f, cases.size)
      for (i <- cases.indices; b <- cases(i)) s.add(i, b)
      for (i <- cases.indices) {
        val d = s.toDouble(i)
        assert(java.lang.Long.parseUnsignedLong(printed(i), 16) == raw(d), s"$f sum $i: C++ ${printed(i)} vs Scala ${raw(d).toHexString} ($d)")
        refSum(f, cases(i)).foreach(v => assert(same(d, nearest(v, s.unitExp)), s"$f sum $i"))
      }
    }
}
