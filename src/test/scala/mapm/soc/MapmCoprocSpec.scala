package mapm.soc

import java.nio.file.{Files, Path, Paths}

import mapm.Slow
import mapm.format.RegisterMap
import mapm.model.TestScenes
import mapm.numerics.FloatFormat
import mapm.params.Fidelity
import mapm.pipeline.{Configure, RtlRun, Tuning}
import mapm.sim.Harness
import org.scalatest.funsuite.AnyFunSuite

/** The coprocessor ([[MapmCoproc]]) in the Verilator harness, driven by the C driver over
  * AXI4-Lite: the frame read back from the frame buffer must equal the model's ([[mapm.numerics.FrameAccum]])
  * bit for bit, every SO on the trace checked, under random memory latency (0-300 cycles),
  * reordered responses and stalled channels, by interrupt and by polling; each bad configuration
  * and each fault injected from the memory side (a malformed record, a bad stream entry, AXI4
  * responses that break a rule or answer an error) ends the pass with its reason, never a hang.
  * Cancels without Verilator. */
@Slow
class MapmCoprocSpec extends AnyFunSuite {
  private def haveVerilator: Boolean = mapm.testutil.HostTools.onPath("verilator")
  private val dir = Paths.get("target/mapm-coproc-test")

  private def scene(name: String, w: Int, h: Int, rays: Int, photons: Int, radius: String): Path = {
    Files.createDirectories(dir)
    val obj = TestScenes.cornellObj.toAbsolutePath.toString
    Files.write(dir.resolve(s"$name.json"),
      s"""{ "obj": "$obj",
         |  "camera": { "position": [278, 273, -530], "direction": [0, 0, 1], "up": [0, 1, 0], "fov": 39.3 },
         |  "lights": [ { "type": "point", "position": [1, 25, 1], "power": [10000000, 10000000, 10000000] } ],
         |  "width": $w, "height": $h, "finalGatherRays": $rays, "photons": $photons, "maxBounces": 4,
         |  "h": $radius, "seed": 5, "directLightSamples": 0 }""".stripMargin.getBytes("UTF-8"))
  }
  private lazy val small = RtlRun.prepare(scene("small", 6, 5, 3, 64, """{ "auto": 12 }""").toString, Some(FloatFormat.fp32), 3, dir.toString, 2, coproc = true)
  private lazy val large = RtlRun.prepare(scene("large", 8, 6, 4, 1000, """{ "auto": 20 }""").toString, Some(FloatFormat.fp32), 3, dir.toString, 2, coproc = true)
  private val stress = Harness.RunOptions(latency = 0, latencyMax = 300, reqStall = 0.2, respGap = 0.2, maxCycles = 5000000)
  private def coproc(t: Int, s: Int, a: Int) = Configure.of(t, s, a, FloatFormat.fp32, 3, tuning = Tuning(coproc = true))

  private def run(prep: RtlRun.Prepared, p: mapm.params.MapmParams, opts: Harness.RunOptions, tag: String): RtlRun.ConfigRun =
    RtlRun.runConfig(prep, p, opts, dir.resolve(s"${prep.name}-${p.name}-$tag"), _ => (), progress = false)

  for ((t, s, a) <- Seq((1, 1, 1), (2, 2, 2), (3, 2, 3)))
    test(s"$t/$s/$a: the frame buffer bit-equal to the model's, every SO exact, under random memory timing, by interrupt and by polling, with and without the stream") {
      assume(haveVerilator, "verilator is not on PATH")
      val p = coproc(t, s, a)
      val runs = Seq((small, stress.copy(seed = 1), "irq"), (small, stress.copy(seed = 2, poll = true, readStream = true), "poll, stream"),
        (large, stress.copy(seed = 3), "large"))
      for ((prep, opts, tag) <- runs) {
        val r = run(prep, p, opts, tag)
        assert(r.passed, s"$tag: ${r.failure}")
        val st = r.outcome.stats.get
        assert(st.soIssued == prep.model.count && st.soPassingCond == prep.model.passing, tag)
        assert(r.frameEqual && r.outcome.frame.isDefined, s"$tag: the frame came from the frame buffer and equals the model's")
      }
    }

  test("timing fidelity: cycles and every (q, photon) checked, the frame the model's") {
    assume(haveVerilator, "verilator is not on PATH")
    val p = Configure.of(2, 2, 2, FloatFormat.fp32, 3, fidelity = Fidelity.Timing, tuning = Tuning(coproc = true))
    val r = run(small, p, stress.copy(seed = 4), "timing")
    assert(r.passed, r.failure)
    assert(r.outcome.frame.isEmpty)
  }

  for ((bad, reason) <- Seq("misaligned" -> RegisterMap.cause("ALIGN").reason, "overlap" -> RegisterMap.cause("OVERLAP").reason,
                            "no-queries" -> RegisterMap.cause("EMPTY").reason, "too-many-pixels" -> RegisterMap.cause("LIMIT").reason,
                            "format" -> "the arrays' number format or slot size is not the MAPM's"))
    test(s"a bad configuration ($bad) ends with its reason, not a hang") {
      assume(haveVerilator, "verilator is not on PATH")
      val r = run(small, coproc(1, 1, 1), Harness.RunOptions(badConfig = Some(bad), maxCycles = 200000), bad)
      assert(!r.outcome.passed && !r.outcome.stopped, bad)
      assert(r.outcome.verdict.contains(reason), s"$bad: ${r.outcome.verdict}")
    }

  /** Each fault the harness injects, the ERROR_CAUSE the pass must end with, and the one other cause
    * it may also show: a read beat that breaks a rule may reach the MAPM's caches before the pass
    * ends, and their miss tables refuse it too (RECORD). */
  private val faults = Seq("node-axis" -> "RECORD", "node-child" -> "RECORD", "query-index" -> "QUERY",
    "unknown-id" -> "AXI_PROTOCOL", "duplicate-response" -> "AXI_PROTOCOL", "early-last" -> "AXI_PROTOCOL",
    "read-error" -> "AXI_READ", "write-error" -> "AXI_WRITE", "stray-b" -> "AXI_PROTOCOL")
  private def alsoAllowed(cause: String): Set[String] = if (cause == "AXI_PROTOCOL") Set("RECORD") else Set.empty

  test("every fault the harness injects is one this spec checks") {
    assert(faults.map(_._1).sorted == Harness.AllFaults.sorted)
  }

  for ((fault, cause) <- faults)
    test(s"an injected $fault ends the pass with $cause and its reason, not a hang") {
      assume(haveVerilator, "verilator is not on PATH")
      val r = run(small, coproc(1, 1, 1), Harness.RunOptions(latency = 5, latencyMax = 80, seed = 7, fault = Some(fault), faultAt = 200,
        maxCycles = 400000), s"fault-$fault")
      val v = r.outcome.verdict
      assert(!r.outcome.passed && !r.outcome.stopped, s"$fault: $v")
      assert(v.contains("driver: ") && v.contains(RegisterMap.cause(cause).reason) && v.contains(s"(injected fault: $fault"), s"$fault: $v")
      for (other <- RegisterMap.causes if other.name != cause && !alsoAllowed(cause)(other.name))
        assert(!v.contains(other.reason), s"$fault: ${other.name} too: $v")
    }
}
