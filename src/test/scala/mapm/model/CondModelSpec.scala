package mapm.model

import mapm.MapmError
import org.scalatest.funsuite.AnyFunSuite

/** CondModel against the exact-rational reference of the same rounded operation sequence. */
class CondModelSpec extends AnyFunSuite {

  private def cond(f: FloatFormat, in: Array[Long]): Boolean =
    CondModel.cond(f, in(0), in(1), in(2), in(3), in(4), in(5), in(6))

  test("e2m1: every 7th of all 16^7 input combinations (38,347,923 cases), specials included") {
    val f = FloatFormat(2, 1)
    val size = 1 << f.width
    // Operation tables of the exact reference, so that millions of cases stay fast.
    def table(op: (FloatFormat, Long, Long) => Long) = Array.tabulate(size, size)((a, b) => op(f, a.toLong, b.toLong).toInt)
    val subT = table(ExactFloat.sub); val addT = table(ExactFloat.add); val mulT = table(ExactFloat.mul)
    val ltT = Array.tabulate(size, size)((a, b) => ExactFloat.lt(f, a.toLong, b.toLong))
    val total = 1L << (7 * f.width)
    val in = new Array[Long](7)
    var k = 0L
    var cases = 0
    var trues = 0
    while (k < total) {
      for (i <- 0 until 7) in(i) = (k >>> (f.width * i)) & f.mask
      val d = Array.tabulate(3)(i => subT(in(i).toInt)(in(i + 3).toInt))
      val d2 = addT(addT(mulT(d(0))(d(0)))(mulT(d(1))(d(1))))(mulT(d(2))(d(2)))
      val want = ltT(d2)(mulT(in(6).toInt)(in(6).toInt))
      if (cond(f, in) != want) fail(s"case ${in.map(f.hex).mkString(",")}: model ${!want}, reference $want")
      if (want) trues += 1
      cases += 1
      k += 7
    }
    info(s"$cases cases, $trues with cond true")
    assert(cases == 38347923 && trues > cases / 200)
  }

  test("fp32: 1,000,000 seeded cases (near the sphere, d2 == hh, zero distance, ties, specials)") {
    val f = FloatFormat.fp32
    val gen = new CondGen(f, 21)
    var trues = 0; var equal = 0; var zero = 0; var withTies = 0
    for (_ <- 0 until 1000000) {
      val in = gen.next()
      val r = CondRef(f, in)
      assert(cond(f, in) == r.cond, s"case ${in.map(f.hex).mkString(",")}: reference ${r.cond}")
      if (r.cond) trues += 1
      if (!f.isNaN(r.d2) && !ExactFloat.lt(f, r.d2, r.hh) && !ExactFloat.lt(f, r.hh, r.d2)) equal += 1
      if (f.isZero(r.d2)) zero += 1
      if (r.ties > 0) withTies += 1
    }
    info(s"cond true $trues, d2 == hh $equal, d2 == 0 $zero, some step rounded a tie $withTies")
    assert(trues > 200000 && trues < 800000)
    assert(equal > 50000 && zero > 50000 && withTies > 20000)
  }

  test("e3m2, e5m4, fp16, bf16, fp64: 100,000 seeded cases each") {
    for (f <- Seq(FloatFormat(3, 2), FloatFormat(5, 4), FloatFormat.fp16, FloatFormat.bf16, FloatFormat.fp64)) {
      val gen = new CondGen(f, 30 + f.width)
      for (_ <- 0 until 100000) {
        val in = gen.next()
        val r = CondRef(f, in)
        assert(cond(f, in) == r.cond, s"$f case ${in.map(f.hex).mkString(",")}: reference ${r.cond}")
      }
    }
  }

  test("named cases and the Vec3 form") {
    val f = FloatFormat.fp32
    // (1,2,2) has length 3: d2 == hh, not inside.
    assert(!CondModel.cond(f, Vec3(1, 2, 2), Vec3.zero, 3.0))
    assert(CondModel.cond(f, Vec3(1, 2, 2), Vec3.zero, 3.0000005))
    assert(CondModel.cond(f, Vec3(5, 5, 5), Vec3(5, 5, 5), 1e-10))    // zero distance
    assert(!CondModel.cond(f, Vec3(5, 5, 5), Vec3(5, 5, 5), 1e-30))   // h*h flushes to 0: 0 < 0 is false
    assert(!CondModel.cond(f, Vec3(3e38, 0, 0), Vec3(-3e38, 0, 0), 3e38)) // d2 and hh overflow: inf < inf
    val err = intercept[MapmError](CondModel.cond(f, Vec3(Double.NaN, 0, 0), Vec3.zero, 1.0))
    assert(err.getMessage.contains("query x"))
  }
}
