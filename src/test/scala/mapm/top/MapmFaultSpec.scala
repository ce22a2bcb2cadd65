package mapm.top

import mapm.pipeline._

import java.nio.file.Paths

import mapm.Slow
import mapm.pipeline.RtlRun
import mapm.numerics.FloatFormat
import mapm.sim.Harness
import org.scalatest.funsuite.AnyFunSuite

/** The faults the harness injects (`--fault`, tools/harness/fault.h) on a whole MAPM's RTL: each
  * must end the run with a FAIL line that names the fault and says how it was caught: the
  * hardware's sticky `io.error` for a malformed node record, a child index beyond the node count,
  * a response with an unknown id and a duplicate response; the memory model's range check for a
  * query whose record address is outside the query array. Never a hang (the cycle limit), never a
  * PASS. Each fault runs on a two-TSM, three-SOA configuration with responses reordered at random.
  *
  * Needs Verilator (cancels without it). */
@Slow
class MapmFaultSpec extends AnyFunSuite {
  private lazy val prep = RtlRun.prepare("test-scenes/cornell-box/scene-small.json", Some(FloatFormat.fp32), 3,
    "target/mapm-fault-test", 2)
  private lazy val params = mapm.pipeline.Configure.of(2, 1, 3, FloatFormat.fp32, 3)
  private val opts = Harness.RunOptions(latency = 5, latencyMax = 80, maxCycles = 400000)

  private val expected = Seq(
    "node-axis" -> "io_error raised", "node-child" -> "io_error raised", "unknown-id" -> "io_error raised",
    "duplicate-response" -> "io_error raised", "query-index" -> "outside the node, photon and query arrays")

  test("every fault the harness injects is one this spec checks") {
    assert(expected.map(_._1).sorted == Harness.Faults.sorted)
  }

  for ((fault, caughtBy) <- expected) test(s"$fault is flagged ($caughtBy)") {
    assume(mapm.testutil.HostTools.onPath("verilator"), "verilator is not on PATH")
    val dir = Paths.get("target/mapm-fault-test").resolve(fault)
    val run = RtlRun.runConfig(prep, params, opts.copy(fault = Some(fault), faultAt = 200), dir, _ => ())
    val v = run.outcome.verdict
    assert(!run.outcome.passed, s"$fault: the run passed")
    assert(v.startsWith("FAIL") && v.contains(caughtBy) && v.contains(s"(injected fault: $fault"), s"$fault: $v")
    assert(!v.contains("watchdog"), s"$fault: $v")
  }

  test("the same configuration passes without a fault") {
    assume(mapm.testutil.HostTools.onPath("verilator"), "verilator is not on PATH")
    val run = RtlRun.runConfig(prep, params, opts, Paths.get("target/mapm-fault-test/none"), _ => ())
    assert(run.passed, run.failure)
  }
}
