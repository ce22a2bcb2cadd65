package mapm.cli

import mapm.numerics.FloatFormat
import org.scalatest.funsuite.AnyFunSuite

/** The options `render` and `sweep` share, as the command line parses them: every option left
  * out takes the default that docs/harness.md states, and given ones reach the harness options. */
class RtlOptionsSpec extends AnyFunSuite {
  private def parse(args: String*): RtlOptions =
    Args.rtlOptionsParser.constructEither(args, allowPositional = false, nameMapper = mainargs.Util.kebabCaseNameMapper)
      .fold(e => fail(s"parse error: $e"), identity)

  test("no option: the documented defaults") {
    val o = parse()
    assert(o.scene == "test-scenes/cornell-box/scene.json" && o.format.isEmpty && o.g == 3 && o.out == "out")
    val h = o.harness()
    assert((h.latency, h.latencyMax, h.bandwidth, h.seed, h.maxCycles, h.clockGhz, h.simThreads) == (100, 0, 14.0, 1L, 0L, 1.5, 1))
    assert((h.queryGap, h.reqStall, h.respGap) == (0.0, 0.0, 0.0) && h.wave.isEmpty)
  }

  test("given options reach the harness options under their kebab-case names") {
    val o = parse("--latency", "7", "--latency-max", "9", "--query-gap", "0.25", "--seed", "42", "-g", "0", "--format", "fp16")
    val h = o.harness()
    assert((h.latency, h.latencyMax, h.queryGap, h.seed) == (7, 9, 0.25, 42L))
    assert(o.g == 0 && o.format.contains(FloatFormat.fp16))
  }
}
