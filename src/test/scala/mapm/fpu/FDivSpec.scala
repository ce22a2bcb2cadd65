package mapm.fpu

import mapm.Slow
import mapm.fpu.FpuTesting._
import mapm.numerics.{FloatFormat, SoftFloat}
import mapm.testutil.Sim
import org.scalatest.funsuite.AnyFunSuite

/** FDiv against SoftFloat (itself checked against exact rationals and the JVM's float and double
  * division), bit for bit, streaming with random idle cycles. */
@Slow
class FDivSpec extends AnyFunSuite with Sim {

  /** `count` quotients a / b, (a, b) = op(i), through FDiv(f, stages) against SoftFloat.div. */
  private def stream(f: FloatFormat, stages: Int, count: Int, op: Int => (Long, Long), seed: Long): StreamCheck.Report =
    StreamCheck.run(pipe(new FDiv(f, stages))(_.io.in, _.io.out), stages, count,
      i => { val (a, b) = op(i); Seq(port(a), port(b)) },
      i => { val (a, b) = op(i); Seq(port(SoftFloat.div(f, a, b))) },
      i => { val (a, b) = op(i); s"${f.hex(a)} / ${f.hex(b)}" }, gap = 0.2, seed)

  test("exhaustive e2m1, e3m2, e4m3, e3m5: every operand pair") {
    for (f <- Seq(FloatFormat(2, 1), FloatFormat(3, 2), FloatFormat(4, 3), FloatFormat(3, 5))) {
      val r = stream(f, FDiv.defaultStages(f), 1 << (2 * f.width), exhaustivePair(f, _), seed = f.width)
      info(s"$f: ${r.operations} operations in ${r.cycles} cycles (${r.idleCycles} idle)")
    }
  }

  test("fp32: 100,000 seeded hard-case pairs; fp16, fp64, e2m52, e11m1: 20,000 each") {
    for ((f, count) <- Seq(FloatFormat.fp32 -> 100000, FloatFormat.fp16 -> 20000, FloatFormat.fp64 -> 20000,
        FloatFormat(2, 52) -> 20000, FloatFormat(11, 1) -> 20000)) {
      val (a, b) = randomPairs(f, count, seed = 70 + f.width)
      val r = stream(f, FDiv.defaultStages(f), count, i => (a(i), b(i)), seed = f.width)
      info(s"$f: ${r.operations} operations in ${r.cycles} cycles")
    }
  }

  test("other depths (0, 1, 2, 5 and every step registered) compute the same, exhaustive at e3m2 and e4m3") {
    for (f <- Seq(FloatFormat(3, 2), FloatFormat(4, 3)); stages <- Seq(0, 1, 2, 5, FDiv.weights(f).length))
      stream(f, stages, 1 << (2 * f.width), exhaustivePair(f, _), seed = 9 + stages)
  }

  test("latency and name follow the depth: fp32 at the default logic per stage") {
    assert(FDiv.digits(FloatFormat.fp32) == 26)
    // 1 + 26 digit steps + 5 adder levels + 3, each step of at most 2.0 alone: 35 stages.
    assert(FDiv.weights(FloatFormat.fp32).length == 35)
    assert(FDiv.defaultStages(FloatFormat.fp32) == 32)
  }
}
