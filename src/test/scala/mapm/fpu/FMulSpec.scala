package mapm.fpu

import mapm.Slow
import mapm.fpu.FpuTesting._
import mapm.numerics.{FloatFormat, SoftFloat}
import mapm.testutil.Sim
import org.scalatest.funsuite.AnyFunSuite

/** FMul against SoftFloat (itself checked against exact rationals), bit for bit, streaming with
  * random idle cycles. */
@Slow
class FMulSpec extends AnyFunSuite with Sim {

  /** `count` products a * b, (a, b) = op(i), through FMul(f, stages) against SoftFloat.mul. */
  private def stream(f: FloatFormat, stages: Int, count: Int, op: Int => (Long, Long), seed: Long): StreamCheck.Report =
    StreamCheck.run(pipe(new FMul(f, stages))(_.io.in, _.io.out), stages, count,
      i => { val (a, b) = op(i); Seq(port(a), port(b)) },
      i => { val (a, b) = op(i); Seq(port(SoftFloat.mul(f, a, b))) },
      i => { val (a, b) = op(i); s"${f.hex(a)} * ${f.hex(b)}" }, gap = 0.2, seed)

  test("exhaustive e2m1, e3m2, e4m3: every operand pair") {
    for (f <- Seq(FloatFormat(2, 1), FloatFormat(3, 2), FloatFormat(4, 3))) {
      val r = stream(f, FMul.defaultStages(f), 1 << (2 * f.width), exhaustivePair(f, _), seed = f.width)
      info(s"$f: ${r.operations} operations in ${r.cycles} cycles (${r.idleCycles} idle)")
    }
  }

  test("fp32: 200,000 seeded hard-case pairs; fp64, e2m52, e11m1: 30,000 each") {
    for ((f, count) <- Seq(FloatFormat.fp32 -> 200000, FloatFormat.fp64 -> 30000, FloatFormat(2, 52) -> 30000, FloatFormat(11, 1) -> 30000)) {
      val (a, b) = randomPairs(f, count, seed = 50 + f.width)
      val r = stream(f, FMul.defaultStages(f), count, i => (a(i), b(i)), seed = f.width)
      info(s"$f: ${r.operations} operations in ${r.cycles} cycles")
    }
  }

  /** `count` squares a * a, a = op(i), through the squarer FMul(f, stages, square = true) against
    * SoftFloat.mul(a, a). */
  private def squares(f: FloatFormat, stages: Int, count: Int, op: Int => Long, seed: Long): StreamCheck.Report =
    StreamCheck.run(pipe(new FMul(f, stages, square = true))(_.io.in, _.io.out), stages, count,
      i => Seq(port(op(i)), port(op(i))),
      i => Seq(port(SoftFloat.mul(f, op(i), op(i)))),
      i => s"${f.hex(op(i))} squared", gap = 0.2, seed)

  test("squarer: every operand of e2m1 … e5m6 and of fp16 and bf16; fp32 and fp64 seeded") {
    for (f <- Seq(FloatFormat(2, 1), FloatFormat(3, 2), FloatFormat(4, 3), FloatFormat(5, 6), FloatFormat.fp16, FloatFormat.bf16)) {
      val r = squares(f, FMul.defaultStages(f), 1 << f.width, _.toLong, seed = 70 + f.width)
      info(s"$f: ${r.operations} squares in ${r.cycles} cycles")
    }
    for ((f, count) <- Seq(FloatFormat.fp32 -> 200000, FloatFormat.fp64 -> 30000)) {
      val (a, _) = randomPairs(f, count, seed = 80 + f.width)
      squares(f, FMul.defaultStages(f), count, a(_), seed = f.width)
    }
  }

  test("squarer at other depths (0, 1, 2, every step registered), every e4m3 operand; fewer steps than stages is refused") {
    val f = FloatFormat(4, 3)
    for (stages <- Seq(0, 1, 2, FMul.weights(f, square = true).length))
      squares(f, stages, 1 << f.width, _.toLong, seed = 90 + stages)
    val steps = FMul.weights(FloatFormat.fp32, square = true).length
    assert(steps < FMul.weights(FloatFormat.fp32).length && FMul.squareFits(FloatFormat.fp32, FMul.defaultStages(FloatFormat.fp32)))
    val e = intercept[IllegalArgumentException](circt.stage.ChiselStage.emitCHIRRTL(new FMul(FloatFormat.fp32, steps + 1, square = true)))
    assert(e.getMessage.contains(s"has $steps steps, fewer than ${steps + 1} stages"), e.getMessage)
  }

  test("other depths (0, 1, 2, 3 and every step registered) compute the same, exhaustive at e3m2 and e4m3") {
    for (f <- Seq(FloatFormat(3, 2), FloatFormat(4, 3)); stages <- Seq(0, 1, 2, 3, FMul.weights(f).length))
      stream(f, stages, 1 << (2 * f.width), exhaustivePair(f, _), seed = 6 + stages)
  }
}
