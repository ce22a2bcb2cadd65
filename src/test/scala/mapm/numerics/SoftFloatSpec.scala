package mapm.numerics

import mapm.Slow
import org.scalatest.funsuite.AnyFunSuite

/** SoftFloat against the exact-rational reference [[ExactFloat]] (exhaustive at tiny formats,
  * seeded random at full width) and against the JVM's own float and double arithmetic. */
@Slow
class SoftFloatSpec extends AnyFunSuite {

  private type Op = (FloatFormat, Long, Long) => Long
  private val ops: Seq[(String, Op, Op)] = Seq(
    ("add", SoftFloat.add, ExactFloat.add),
    ("sub", SoftFloat.sub, ExactFloat.sub),
    ("mul", SoftFloat.mul, ExactFloat.mul),
    ("div", SoftFloat.div, ExactFloat.div))

  private def check(f: FloatFormat, name: String, got: Long, want: Long, a: Long, b: Long): Unit =
    if (got != want)
      fail(s"$f $name(${f.hex(a)}, ${f.hex(b)}) = ${f.hex(got)}, reference ${f.hex(want)}")

  test("exhaustive: every operand pair of e2m1, e3m2, e4m3, e2m5, e5m2, e3m4 (all patterns, specials included)") {
    for (f <- Seq(FloatFormat(2, 1), FloatFormat(3, 2), FloatFormat(4, 3), FloatFormat(2, 5), FloatFormat(5, 2), FloatFormat(3, 4))) {
      val all = 0L until (1L << f.width)
      for (a <- all; b <- all) {
        for ((name, op, ref) <- ops) check(f, name, op(f, a, b), ref(f, a, b), a, b)
        assert(SoftFloat.lt(f, a, b) == ExactFloat.lt(f, a, b), s"$f lt(${f.hex(a)}, ${f.hex(b)})")
      }
    }
  }

  test("fp32: 1,000,000 seeded hard-case pairs per operation against exact rationals, ties counted") {
    val f = FloatFormat.fp32
    for (((name, op, ref), k) <- ops.zipWithIndex) {
      val g = new FloatGen(f, 100 + k)
      val count = if (name == "div") 300000 else 1000000
      var ties = 0
      var cancellations = 0
      for (_ <- 0 until count) {
        val (a, b) = g.pair()
        val want = ref(f, a, b)
        check(f, name, op(f, a, b), want, a, b)
        val exact = name match {
          case "add" => ExactFloat.sum(ExactFloat.decode(f, a), ExactFloat.decode(f, b))
          case "sub" => ExactFloat.sum(ExactFloat.decode(f, a), ExactFloat.negate(ExactFloat.decode(f, b)))
          case "mul" => ExactFloat.product(ExactFloat.decode(f, a), ExactFloat.decode(f, b))
          case _     => ExactFloat.quotient(ExactFloat.decode(f, a), ExactFloat.decode(f, b))
        }
        if (ExactFloat.isTie(f, exact)) ties += 1
        if ((name == "add" || name == "sub") && f.isFinite(a) && f.isFinite(b) && f.expField(a) != 0 && f.expField(want) < f.expField(a) - 8) cancellations += 1
      }
      info(s"$name: $count pairs, $ties exact ties" + (if (cancellations > 0) s", $cancellations with more than 8 bits cancelled" else ""))
      if (name != "div") assert(ties > count / 50, s"$name: too few ties ($ties) to exercise rounding")
      if (name == "add" || name == "sub") assert(cancellations > count / 100)
    }
  }

  test("fp32: 1,000,000 comparisons against exact rationals, equal operands included") {
    val f = FloatFormat.fp32
    val g = new FloatGen(f, 7)
    var equal = 0
    for (_ <- 0 until 1000000) {
      val (a, b) = g.pair()
      val want = ExactFloat.lt(f, a, b)
      assert(SoftFloat.lt(f, a, b) == want, s"lt(${f.hex(a)}, ${f.hex(b)})")
      if (!want && !ExactFloat.lt(f, b, a) && !f.isNaN(a) && !f.isNaN(b)) equal += 1
    }
    assert(equal > 50000, s"only $equal equal pairs")
  }

  test("many formats: 30,000 seeded pairs per operation and format against exact rationals") {
    val formats = Seq(FloatFormat(2, 52), FloatFormat(11, 52), FloatFormat(11, 1), FloatFormat(8, 30),
      FloatFormat(8, 31), FloatFormat(6, 29), FloatFormat(5, 10), FloatFormat(8, 7), FloatFormat(3, 40),
      FloatFormat(10, 20), FloatFormat(2, 1), FloatFormat(7, 45))
    for ((f, i) <- formats.zipWithIndex) {
      val g = new FloatGen(f, 1000 + i)
      for (_ <- 0 until 30000) {
        val (a, b) = g.pair()
        for ((name, op, ref) <- ops) check(f, name, op(f, a, b), ref(f, a, b), a, b)
        assert(SoftFloat.lt(f, a, b) == ExactFloat.lt(f, a, b), s"$f lt(${f.hex(a)}, ${f.hex(b)})")
      }
    }
  }

  test("fp32 equals the JVM's float arithmetic wherever flushing cannot interfere (2,000,000 pairs per op)") {
    val f = FloatFormat.fp32
    val g = new FloatGen(f, 11)
    def fl(b: Long): Float = java.lang.Float.intBitsToFloat(b.toInt)
    val jvm: Seq[(String, Op, (Float, Float) => Float)] =
      Seq(("add", SoftFloat.add, _ + _), ("sub", SoftFloat.sub, _ - _), ("mul", SoftFloat.mul, _ * _), ("div", SoftFloat.div, _ / _))
    var compared = 0
    for (_ <- 0 until 2000000) {
      val (a, b) = g.pair()
      if (!f.isZero(a) || f.manField(a) == 0) if (!f.isZero(b) || f.manField(b) == 0) { // no denormal inputs
        for ((name, op, jop) <- jvm) {
          val r = jop(fl(a), fl(b))
          val got = op(f, a, b)
          if (r.isNaN) assert(f.isNaN(got), s"$name(${f.hex(a)}, ${f.hex(b)}) should be NaN")
          else if (r == 0f || math.abs(r) > java.lang.Float.MIN_NORMAL) {
            compared += 1
            check(f, name, got, java.lang.Float.floatToRawIntBits(r).toLong & f.mask, a, b)
          }
        }
      }
    }
    info(s"$compared results compared bit for bit")
    assert(compared > 6000000)
  }

  test("fp64 equals the JVM's double arithmetic wherever flushing cannot interfere (1,000,000 pairs per op)") {
    val f = FloatFormat.fp64
    val g = new FloatGen(f, 12)
    def d(b: Long): Double = java.lang.Double.longBitsToDouble(b)
    val jvm: Seq[(String, Op, (Double, Double) => Double)] =
      Seq(("add", SoftFloat.add, _ + _), ("sub", SoftFloat.sub, _ - _), ("mul", SoftFloat.mul, _ * _), ("div", SoftFloat.div, _ / _))
    var compared = 0
    for (_ <- 0 until 1000000) {
      val (a, b) = g.pair()
      if (!f.isZero(a) || f.manField(a) == 0) if (!f.isZero(b) || f.manField(b) == 0) {
        for ((name, op, jop) <- jvm) {
          val r = jop(d(a), d(b))
          val got = op(f, a, b)
          if (r.isNaN) assert(f.isNaN(got), s"$name(${f.hex(a)}, ${f.hex(b)}) should be NaN")
          else if (r == 0.0 || math.abs(r) > java.lang.Double.MIN_NORMAL) {
            compared += 1
            check(f, name, got, java.lang.Double.doubleToRawLongBits(r), a, b)
          }
        }
      }
    }
    info(s"$compared results compared bit for bit")
    assert(compared > 3000000)
  }

  test("named cases: signed zeros, x - x, infinities, NaN, overflow, flush of a tiny difference") {
    val f = FloatFormat.fp32
    def b(x: Float): Long = java.lang.Float.floatToRawIntBits(x).toLong & f.mask
    val negZero = f.pack(1, 0, 0)
    assert(SoftFloat.sub(f, b(1.5f), b(1.5f)) == 0L)                    // x - x = +0
    assert(SoftFloat.add(f, negZero, negZero) == negZero)                 // -0 + -0 = -0
    assert(SoftFloat.add(f, negZero, 0L) == 0L)
    assert(SoftFloat.mul(f, b(-2f), 0L) == negZero)
    assert(SoftFloat.add(f, f.posInf, b(-1e30f)) == f.posInf)
    assert(SoftFloat.sub(f, f.posInf, f.posInf) == f.quietNaN)
    assert(SoftFloat.mul(f, f.posInf, 0L) == f.quietNaN)
    assert(SoftFloat.div(f, b(1f), negZero) == f.pack(1, f.expMax, 0))
    assert(SoftFloat.mul(f, b(3e38f), b(2f)) == f.posInf)                 // overflow to infinity
    assert(SoftFloat.mul(f, b(-1e-30f), b(1e-10f)) == negZero)            // underflow to signed zero
    val minN = f.pack(0, 1, 0)
    assert(SoftFloat.sub(f, f.pack(0, 1, 1), minN) == 0L)                 // denormal difference flushed to +0
    assert(SoftFloat.sub(f, minN, f.pack(0, 1, 1)) == negZero)            // ... keeping the exact result's sign
    assert(SoftFloat.add(f, f.pack(0, 3, 5), f.pack(0, 3, 0)) == f.pack(0, 4, 2)) // 5/2 rounds to even 2
    assert(!SoftFloat.lt(f, negZero, 0L) && !SoftFloat.lt(f, 0L, negZero))
    assert(!SoftFloat.lt(f, f.quietNaN, f.posInf) && !SoftFloat.lt(f, 0L, f.quietNaN))
    assert(SoftFloat.lt(f, f.pack(1, f.expMax, 0), b(-1e38f)))
    assert(!SoftFloat.lt(f, f.pack(0, 0, 5), f.pack(1, 0, 9)))          // denormal patterns are zeros
  }
}
