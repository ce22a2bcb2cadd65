package mapm.fpu

import mapm.model.FloatFormat
import org.scalatest.funsuite.AnyFunSuite

/** `verilator --lint-only -Wall` finds nothing in the emitted units, across formats and cuts. */
class FpuLintSpec extends AnyFunSuite {
  private val formats = Seq(FloatFormat(2, 1), FloatFormat(3, 2), FloatFormat.fp16, FloatFormat.bf16,
    FloatFormat.fp32, FloatFormat.fp64, FloatFormat(2, 52), FloatFormat(11, 1))

  for (f <- formats) test(s"FAdd, FMul, FCmpLt at $f lint clean") {
    for (gen <- Seq(() => new FAdd(f), () => new FMul(f), () => new FCmpLt(f))) {
      val (top, messages) = LintCheck(gen())
      assert(messages.isEmpty, s"$top:\n${messages.mkString("\n")}")
    }
  }

  // (With every cut left out a unit is combinational and lint rightly notes its unused clock.)
  test("units with some cuts left out lint clean") {
    val f = FloatFormat.fp32
    for (gen <- Seq(() => new FAdd(f, Seq(true, false, true, false)), () => new FAdd(f, Seq(false, false, false, true)),
                    () => new FMul(f, Seq(false, true, false)), () => new FMul(f, Seq(false, false, true)))) {
      val (top, messages) = LintCheck(gen())
      assert(messages.isEmpty, s"$top:\n${messages.mkString("\n")}")
    }
  }
}
