package mapm.soc

import chisel3._
import chiseltest._
import mapm.numerics.{FloatFormat, FrameAccum}
import mapm.testutil.Sim
import org.scalatest.funsuite.AnyFunSuite

/** [[FrameConvert]] and [[FrameResolve]] against the model ([[FrameAccum]], itself checked against
  * exact rationals): every e4m3 pattern at every scale that matters, every 12-bit sum; random fp32
  * values and 64-bit sums. */
class FrameArithSpec extends AnyFunSuite with Sim {
  private def convertCheck(fa: FrameAccum, cases: Iterator[(Long, Int)]): Int = {
    var n = 0
    simulate(new FrameConvert(fa)) { c =>
      for ((bits, scale) <- cases) {
        c.io.in.poke(bits.U); c.io.scale.poke(scale.S)
        val what = s"${fa.format} bits 0x${bits.toHexString} scale $scale"
        fa.convert(bits, scale) match {
          case Left(FrameAccum.NonFinite) => assert(c.io.nonFinite.peek().litToBoolean && !c.io.range.peek().litToBoolean, what)
          case Left(_) => assert(c.io.range.peek().litToBoolean && !c.io.nonFinite.peek().litToBoolean, what)
          case Right(v) =>
            assert(!c.io.range.peek().litToBoolean && !c.io.nonFinite.peek().litToBoolean, what)
            assert(c.io.out.peek().litValue == v, what)
        }
        n += 1
      }
    }
    n
  }

  test("convert: every e4m3 pattern at scales -14..6 (16-bit sums, 4-bit counts)") {
    val fa = FrameAccum(FloatFormat(4, 3), 16, 4)
    assert(convertCheck(fa, for (b <- (0L until 256L).iterator; s <- -14 to 6) yield (b, s)) == 256 * 21)
  }

  test("convert: 20,000 random fp32 values at random scales (64-bit sums, 24-bit counts), and the fp32 edges") {
    val f = FloatFormat.fp32
    val fa = FrameAccum.default(f)
    val rnd = new scala.util.Random(36)
    val edges = Seq(0L, f.posInf, f.quietNaN, f.pack(1, 0, 5), f.pack(0, 1, 0), f.pack(1, f.expMax - 1, f.manMask))
      .flatMap(b => Seq(-200, -40, 0, 100).map(s => (b, s)))
    val random = Iterator.fill(20000) {
      val b = rnd.nextLong() & f.mask
      (b, f.expField(b) - f.bias - 60 + rnd.nextInt(70)) // around the scales where it fits, rounds or overflows
    }
    convertCheck(fa, edges.iterator ++ random)
  }

  private def resolveCheck(fa: FrameAccum, cases: Iterator[(BigInt, Int)]): Unit =
    simulate(new FrameResolve(fa)) { c =>
      for ((sum, scale) <- cases) {
        c.io.sum.poke(sum.S); c.io.scale.poke(scale.S)
        assert(c.io.out.peek().litValue == BigInt(fa.resolve(sum, scale)) % (BigInt(1) << fa.format.width), s"${fa.format} sum $sum scale $scale")
      }
    }

  test("resolve: every 12-bit sum to e4m3 at scales -16..6 (flush, overflow, ties)") {
    val fa = FrameAccum(FloatFormat(4, 3), 16, 4)
    resolveCheck(fa, for (s <- (-(1 << 11) until (1 << 11)).iterator; sc <- Seq(-16, -12, -9, -6, -3, 0, 3, 6)) yield (BigInt(s), sc))
  }

  test("resolve: 20,000 random 64-bit sums to fp32 at random scales, and the extremes") {
    val fa = FrameAccum.default(FloatFormat.fp32)
    val rnd = new scala.util.Random(37)
    val extremes = Seq(BigInt(0), BigInt(1), BigInt(-1), -(BigInt(1) << 63), (BigInt(1) << 63) - 1).flatMap(v => Seq(-200, -40, 0, 90).map(s => (v, s)))
    val random = Iterator.fill(20000) {
      val bits = 1 + rnd.nextInt(63)
      val v = BigInt(bits, rnd) * (if (rnd.nextBoolean()) -1 else 1)
      (v, -180 + rnd.nextInt(260))
    }
    resolveCheck(fa, extremes.iterator ++ random)
  }
}
