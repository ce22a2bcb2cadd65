package mapm.fpu

import mapm.Slow
import mapm.fpu.FpuTesting._
import mapm.numerics.{FloatFormat, SoftFloat}
import mapm.testutil.Sim
import org.scalatest.funsuite.AnyFunSuite

/** FCmpLt against SoftFloat.lt (itself checked against exact rationals), streaming with random
  * idle cycles. */
@Slow
class FCmpLtSpec extends AnyFunSuite with Sim {

  /** `count` comparisons a < b, (a, b) = op(i), through FCmpLt(f, stages) against SoftFloat.lt. */
  private def stream(f: FloatFormat, stages: Int, count: Int, op: Int => (Long, Long), seed: Long): StreamCheck.Report =
    StreamCheck.run(pipe(new FCmpLt(f, stages))(_.io.in, _.io.out), stages, count,
      i => { val (a, b) = op(i); Seq(port(a), port(b)) },
      i => { val (a, b) = op(i); Seq(if (SoftFloat.lt(f, a, b)) 1 else 0) },
      i => { val (a, b) = op(i); s"${f.hex(a)} < ${f.hex(b)}" }, gap = 0.2, seed)

  test("exhaustive e4m3 and e2m5: every operand pair") {
    for (f <- Seq(FloatFormat(4, 3), FloatFormat(2, 5)))
      stream(f, 1, 1 << (2 * f.width), exhaustivePair(f, _), seed = f.width)
  }

  test("fp32: 200,000 seeded pairs (equal, negated, zeros, NaN among them); fp64: 30,000") {
    for ((f, count) <- Seq(FloatFormat.fp32 -> 200000, FloatFormat.fp64 -> 30000)) {
      val (a, b) = randomPairs(f, count, seed = 60 + f.width)
      stream(f, 1, count, i => (a(i), b(i)), seed = f.width)
    }
  }

  test("without its register (latency 0), exhaustive at e3m2") {
    val f = FloatFormat(3, 2)
    stream(f, 0, 1 << (2 * f.width), exhaustivePair(f, _), seed = 7)
  }
}
