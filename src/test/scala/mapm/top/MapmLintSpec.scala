package mapm.top

import mapm.pipeline.Configure

import mapm.Slow
import mapm.format.SlotLayout
import mapm.params._
import mapm.numerics.FloatFormat
import mapm.sim.{Harness, Lint, MapmRtl}
import org.scalatest.funsuite.AnyFunSuite

/** The whole MAPM's emitted SystemVerilog passes `verilator --lint-only -Wall` without a single
  * warning (DECLFILENAME off: one file holds the top and every submodule): the README's default
  * configuration (16/16/2 fp32 g 3), presets of Table 4.8 with power-of-two and other SOM counts
  * and 3 SOAs per SOM, odd counts, formats from 16 bits (packed and wide) to fp64, and the smallest
  * Register-queue bank. `tools/mapm lint` lints all 24 presets (a benchmark: about 15 minutes). */
@Slow
class MapmLintSpec extends AnyFunSuite {
  private def haveVerilator: Boolean =
    mapm.testutil.HostTools.onPath("verilator")

  private val configs = Seq(
    MapmParams.default,
    MapmParams.presets("4/6/3"),
    MapmParams.presets("2/3/2"),
    Configure.of(1, 1, 2, FloatFormat.fp32, 3),
    Configure.of(3, 2, 3, FloatFormat.fp16, 2),
    Configure.of(2, 3, 1, FloatFormat.bf16, 0, tuning = mapm.pipeline.Tuning(registerQueueDepth = Some(26))),
    Configure.of(1, 1, 1, FloatFormat(6, 9), 3),
    Configure.of(1, 1, 2, FloatFormat.fp16, 3, layout = SlotLayout.Wide),
    Configure.of(1, 1, 1, FloatFormat.fp64, 3),
    Configure.of(2, 3, 2, FloatFormat.fp32, 3, tuning = mapm.pipeline.Tuning(sopL2Banks = Some(8), tsL2Banks = Some(2))))

  for (p <- configs) test(s"Mapm_${p.name} lints clean") {
    assume(haveVerilator, "verilator is not on PATH")
    val (dir, top) = MapmRtl.emit(p)
    val w = Lint.warnings(Harness.svFiles(dir), top)
    assert(w.isEmpty, s"$top lint:\n${w.take(40).mkString("\n")}")
  }
}
