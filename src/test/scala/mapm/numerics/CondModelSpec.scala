package mapm.numerics

import mapm.Slow
import mapm.MapmError
import org.scalatest.funsuite.AnyFunSuite

/** CondModel against the exact-rational reference of the same rounded operation sequence. */
@Slow
class CondModelSpec extends AnyFunSuite {

  private def cond(f: FloatFormat, in: Array[Long]): Boolean =
    CondModel.cond(f, in(0), in(1), in(2), in(3), in(4), in(5), in(6))

  test("e2m1: all 16^7 = 268,435,456 input combinations (every pattern: zeros, denormal patterns, infinities, NaNs) against the exact reference") {
    val f = FloatFormat(2, 1)
    val t = new CondTables(f)
    val s = t.size
    final class Counts { var cases, trues, equal, zero, ties, errors = 0L; var first = List.empty[String] }
    // Work shared by h (16 slices of 16^6 cases) among the available cores.
    val nextH = new java.util.concurrent.atomic.AtomicInteger(0)
    def slice(c: Counts): Unit = {
      var h = nextH.getAndIncrement()
      while (h < s) {
        val hh = t.mul(h * s + h); val tieH = t.mulTie(h * s + h)
        for (qz <- 0 until s; pz <- 0 until s) {
          val dz = t.sub(qz * s + pz); val sz = t.mul(dz * s + dz); val tieZ = t.subTie(qz * s + pz) || t.mulTie(dz * s + dz)
          for (qy <- 0 until s; py <- 0 until s) {
            val dy = t.sub(qy * s + py); val sy = t.mul(dy * s + dy); val tieY = t.subTie(qy * s + py) || t.mulTie(dy * s + dy)
            for (qx <- 0 until s; px <- 0 until s) {
              val dx = t.sub(qx * s + px); val sx = t.mul(dx * s + dx)
              val xy = t.add(sx * s + sy); val d2 = t.add(xy * s + sz)
              val want = t.lt(d2 * s + hh)
              val got = CondModel.cond(f, qx, qy, qz, px, py, pz, h)
              if (got != want) {
                c.errors += 1
                if (c.errors <= 5) c.first ::= s"case ${Seq(qx, qy, qz, px, py, pz, h).map(v => f.hex(v.toLong)).mkString(",")}: model $got, reference $want"
              }
              c.cases += 1
              if (want) c.trues += 1
              if (t.eq(d2 * s + hh)) c.equal += 1
              if (f.isZero(d2)) c.zero += 1
              if (tieH || tieZ || tieY || t.subTie(qx * s + px) || t.mulTie(dx * s + dx) || t.addTie(sx * s + sy) || t.addTie(xy * s + sz)) c.ties += 1
            }
          }
        }
        h = nextH.getAndIncrement()
      }
    }
    val t0 = System.nanoTime
    val counts = Seq.fill(math.max(1, Runtime.getRuntime.availableProcessors))(new Counts)
    val threads = counts.map(c => new Thread(() => slice(c)))
    threads.foreach(_.start()); threads.foreach(_.join())
    def sum(g: Counts => Long) = counts.map(g).sum
    assert(sum(_.errors) == 0, s"${sum(_.errors)} mismatches, some:\n${counts.flatMap(_.first).mkString("\n")}")
    info(f"${sum(_.cases)} cases in ${(System.nanoTime - t0) / 1e9}%.1f s: cond true ${sum(_.trues)}, d2 == hh ${sum(_.equal)}, d2 == 0 ${sum(_.zero)}, some step rounded a tie ${sum(_.ties)}")
    assert(sum(_.cases) == (1L << 28))
    assert(sum(_.trues) > 0 && sum(_.equal) > 0 && sum(_.zero) > 0 && sum(_.ties) > 0)
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
