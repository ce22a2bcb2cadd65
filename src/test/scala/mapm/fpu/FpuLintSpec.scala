package mapm.fpu

import mapm.numerics.FloatFormat
import org.scalatest.funsuite.AnyFunSuite

/** `verilator --lint-only -Wall` finds nothing in the emitted units, across formats and cuts. */
class FpuLintSpec extends AnyFunSuite {
  private val formats = Seq(FloatFormat(2, 1), FloatFormat(3, 2), FloatFormat.fp16, FloatFormat.bf16,
    FloatFormat.fp32, FloatFormat.fp64, FloatFormat(2, 52), FloatFormat(11, 1))

  for (f <- formats) test(s"FAdd, FMul, FDiv, FCmpLt at $f lint clean") {
    for (gen <- Seq(() => new FAdd(f), () => new FMul(f), () => new FDiv(f), () => new FCmpLt(f),
                    () => new FAdd(f, FAdd.defaultStages(f), stallable = true, direction = true))) {
      val (top, messages) = LintCheck(gen())
      assert(messages.isEmpty, s"$top:\n${messages.mkString("\n")}")
    }
  }

  // (At depth 0 a unit is combinational and lint rightly notes its unused clock.)
  test("units at other depths (1, 3 and every step registered) lint clean") {
    val f = FloatFormat.fp32
    for (gen <- Seq(() => new FAdd(f, 1), () => new FAdd(f, 3), () => new FAdd(f, FAdd.weights(f).length),
                    () => new FMul(f, 1), () => new FMul(f, 3), () => new FMul(f, FMul.weights(f).length),
                    () => new FDiv(f, 1), () => new FDiv(f, 5), () => new FDiv(f, FDiv.weights(f).length))) {
      val (top, messages) = LintCheck(gen())
      assert(messages.isEmpty, s"$top:\n${messages.mkString("\n")}")
    }
  }
}
