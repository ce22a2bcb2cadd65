package mapm.shader

import mapm.Slow
import mapm.fpu.{FpuDepth, LintCheck}
import mapm.numerics.{Arith, FloatFormat}
import mapm.tsearch.ConvTSA
import org.scalatest.funsuite.AnyFunSuite

/** `verilator --lint-only -Wall` finds nothing in the conventional SOA and TSA (split per module,
  * no waivers), at several formats, stallable or not. */
@Slow
class ConvLintSpec extends AnyFunSuite {
  for (f <- Seq(FloatFormat.fp32, FloatFormat.fp16, FloatFormat.bf16, FloatFormat(3, 3)))
    test(s"ConvSOA and ConvTSA at $f lint clean") {
      val gens = Seq(() => new ConvTSA(f, 16, addStages = FpuDepth.of(f).add),
        () => new ConvTSA(f, 12, stallable = true, addStages = FpuDepth.of(f).add)) ++
        (if (f.manWidth >= 4) Seq(() => new SOA(f, 3, 16, arith = Arith.Conventional)) else Seq.empty)
      for (gen <- gens) {
        val (top, messages) = LintCheck(gen())
        assert(messages.isEmpty, s"$top:\n${messages.mkString("\n")}")
      }
    }
}
