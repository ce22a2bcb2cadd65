package mapm.fpu

import mapm.Slow
import mapm.fpu.FpuTesting._
import mapm.numerics.{FloatFormat, SoftFloat}
import mapm.testutil.Sim
import org.scalatest.funsuite.AnyFunSuite

/** FAdd against SoftFloat (itself checked against exact rationals), bit for bit, streaming with
  * random idle cycles. */
@Slow
class FAddSpec extends AnyFunSuite with Sim {

  /** Runs `count` operations (a, b, sub) through FAdd(f, stages) and checks every result. */
  private def stream(f: FloatFormat, stages: Int, count: Int, op: Int => (Long, Long, Boolean), seed: Long): StreamCheck.Report =
    StreamCheck.run(pipe(new FAdd(f, stages))(_.io.in, _.io.out), stages, count,
      i => { val (a, b, s) = op(i); Seq(port(a), port(b), if (s) 1 else 0) },
      i => { val (a, b, s) = op(i); Seq(port(if (s) SoftFloat.sub(f, a, b) else SoftFloat.add(f, a, b))) },
      i => { val (a, b, s) = op(i); s"${f.hex(a)} ${if (s) "-" else "+"} ${f.hex(b)}" }, gap = 0.2, seed)

  private def exhaustive(f: FloatFormat, i: Int): (Long, Long, Boolean) = {
    val (a, b) = exhaustivePair(f, i >> 1)
    (a, b, (i & 1) == 1)
  }

  test("exhaustive e2m1, e3m2, e4m3: every operand pair, added and subtracted") {
    for (f <- Seq(FloatFormat(2, 1), FloatFormat(3, 2), FloatFormat(4, 3))) {
      val r = stream(f, FAdd.defaultStages(f), 2 << (2 * f.width), exhaustive(f, _), seed = f.width)
      info(s"$f: ${r.operations} operations in ${r.cycles} cycles (${r.idleCycles} idle)")
    }
  }

  test("fp32: 200,000 seeded hard-case pairs; fp64, e2m52, e11m1: 30,000 each") {
    for ((f, count) <- Seq(FloatFormat.fp32 -> 200000, FloatFormat.fp64 -> 30000, FloatFormat(2, 52) -> 30000, FloatFormat(11, 1) -> 30000)) {
      val (a, b) = randomPairs(f, count, seed = 40 + f.width)
      val r = stream(f, FAdd.defaultStages(f), count, i => (a(i), b(i), (i & 1) == 1), seed = f.width)
      info(s"$f: ${r.operations} operations in ${r.cycles} cycles")
    }
  }

  test("other depths (0, 1, 2, 4 and every step registered) compute the same, exhaustive at e3m2 and e4m3") {
    for (f <- Seq(FloatFormat(3, 2), FloatFormat(4, 3)); stages <- Seq(0, 1, 2, 4, FAdd.weights(f).length))
      stream(f, stages, 2 << (2 * f.width), exhaustive(f, _), seed = 5 + stages)
  }
}
