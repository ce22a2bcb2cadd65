package mapm.top

import java.nio.file.Files

import mapm.Slow
import mapm.format.SlotLayout
import mapm.params._
import mapm.model.FloatFormat
import mapm.sim.{Emit, Verilator}
import org.scalatest.funsuite.AnyFunSuite
import scala.sys.process._

/** The whole MAPM's emitted SystemVerilog passes `verilator --lint-only -Wall` without a single
  * warning (DECLFILENAME off: one file holds the top and every submodule), for power-of-two and
  * other lane counts, formats from 16 bits (packed and wide) to fp64, and the smallest
  * Register-queue bank. */
@Slow
class MapmLintSpec extends AnyFunSuite {
  private def haveVerilator: Boolean =
    mapm.testutil.HostTools.onPath("verilator")

  private val configs = Seq(
    MapmParams.of(1, 1, 2, FloatFormat.fp32, 3),
    MapmParams.of(3, 2, 3, FloatFormat.fp16, 2),
    MapmParams.of(2, 3, 1, FloatFormat.bf16, 0, registerQueueDepth = Some(26)),
    MapmParams.of(1, 1, 1, FloatFormat(6, 9), 3),
    MapmParams.of(1, 1, 2, FloatFormat.fp16, 3, layout = SlotLayout.Wide),
    MapmParams.of(1, 1, 1, FloatFormat.fp64, 3))

  for (p <- configs) test(s"Mapm_${p.name} lints clean") {
    assume(haveVerilator, "verilator is not on PATH")
    val dir = Files.createTempDirectory("mapm-lint")
    val file = Emit.toFile(new Mapm(p), dir, s"Mapm_${p.name}.sv")
    val log = new StringBuilder
    val rc = Process(Seq(Verilator.executable, "--lint-only", "-Wall", "-Wno-DECLFILENAME", "--top-module", s"Mapm_${p.name}", file.toString))
      .!(ProcessLogger(l => log.append(l).append('\n'), l => log.append(l).append('\n')))
    assert(rc == 0 && log.isEmpty, s"Mapm_${p.name} lint:\n${log.toString.linesIterator.take(40).mkString("\n")}")
  }
}
