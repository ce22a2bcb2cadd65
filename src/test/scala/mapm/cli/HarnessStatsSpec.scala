package mapm.cli

import java.nio.file.{Files, Paths}

import mapm.MapmError
import mapm.sim.HarnessStats
import org.scalatest.funsuite.AnyFunSuite

/** [[HarnessStats]]: a stats.json in the harness's layout (tools/harness/main.cpp), written here
  * with known values, reads into the typed fields; a missing or mistyped key is one clear error. */
class HarnessStatsSpec extends AnyFunSuite {
  private val text =
    """{
      |  "top": "Mapm_1_1_2",
      |  "config": { "tsm": 1, "som": 1, "soaPerSom": 2, "expWidth": 8 },
      |  "result": "PASS",
      |  "failure": null,
      |  "seed": 7,
      |  "latency": 100,
      |  "latencyMax": 300,
      |  "queryGap": 0.25,
      |  "reqStall": 0.125,
      |  "respGap": 0.5,
      |  "bandwidthBytesPerCycle": 14,
      |  "clockGHz": 1.5,
      |  "cycles": 123456,
      |  "queries": 48,
      |  "queriesCompleted": 47,
      |  "soIssued": 9000,
      |  "soPassingCond": 4000,
      |  "soPerCycle": 0.0729,
      |  "tsOps": 5000,
      |  "tsOpsPerCycle": 0.0405,
      |  "stallCycles": { "stallQuery": 11, "stallRqFull": 12 },
      |  "caches": { "tsL1": { "hits": 30, "misses": 10, "hitRate": 0.75 }, "soq": { "hits": 0, "misses": 0, "hitRate": 0 } },
      |  "memoryRequests": 321,
      |  "bytesFetched": 10272,
      |  "bytesPerCycle": 0.0832,
      |  "gbPerSecond": 0.1248,
      |  "counters": { "queries": 48, "tsOps": 5000, "stallQuery": 11, "stallRqFull": 12, "rqPeak": 9 },
      |  "wallSeconds": 2.5,
      |  "simulatedCyclesPerSecond": 49382.4
      |}""".stripMargin

  test("every key the harness writes reads into its field") {
    val path = Paths.get("target/harness-stats-test/stats.json")
    Files.createDirectories(path.getParent)
    Files.write(path, text.getBytes("UTF-8"))
    val s = HarnessStats.read(path)
    assert(s.top == "Mapm_1_1_2")
    assert(s.config.toSeq == Seq("tsm" -> 1L, "som" -> 1L, "soaPerSom" -> 2L, "expWidth" -> 8L))
    assert(s.result == "PASS" && s.failure.isEmpty)
    assert(s.seed == 7 && s.latency == 100 && s.latencyMax == 300)
    assert(s.queryGap == 0.25 && s.reqStall == 0.125 && s.respGap == 0.5)
    assert(s.bandwidthBytesPerCycle == 14.0 && s.clockGHz == 1.5)
    assert(s.cycles == 123456L && s.queries == 48 && s.queriesCompleted == 47)
    assert(s.soIssued == 9000 && s.soPassingCond == 4000 && s.soPerCycle == 0.0729)
    assert(s.tsOps.contains(5000L) && s.tsOpsPerCycle.contains(0.0405))
    assert(s.stallCycles.toSeq == Seq("stallQuery" -> 11L, "stallRqFull" -> 12L))
    assert(s.caches.toSeq == Seq("tsL1" -> HarnessStats.Cache(30, 10, 0.75), "soq" -> HarnessStats.Cache(0, 0, 0.0)))
    assert(s.memoryRequests == 321 && s.bytesFetched == 10272 && s.bytesPerCycle == 0.0832 && s.gbPerSecond == 0.1248)
    assert(s.counters.toSeq == Seq("queries" -> 48L, "tsOps" -> 5000L, "stallQuery" -> 11L, "stallRqFull" -> 12L, "rqPeak" -> 9L))
    assert(s.wallSeconds == 2.5 && s.simulatedCyclesPerSecond == 49382.4)
    assert(s.json == ujson.read(text), "the file as read, every key kept")
  }

  test("a failed run without a TS-op counter or a configuration block") {
    val failed = text.replace("\"result\": \"PASS\"", "\"result\": \"FAIL\"").replace("\"failure\": null", "\"failure\": \"watchdog\"")
      .replaceFirst("\"tsOps\": 5000,", "\"tsOps\": null,").replace("\"tsOpsPerCycle\": 0.0405", "\"tsOpsPerCycle\": null")
      .replace("\"config\": { \"tsm\": 1, \"som\": 1, \"soaPerSom\": 2, \"expWidth\": 8 },", "")
    val s = HarnessStats.parse(failed, "failed.json")
    assert(s.result == "FAIL" && s.failure.contains("watchdog"))
    assert(s.tsOps.isEmpty && s.tsOpsPerCycle.isEmpty && s.config.isEmpty)
    assert(s.counters("tsOps") == 5000L)
  }

  test("a missing, mistyped or fractional key, or no JSON at all, is one clear error") {
    def error(t: String): String = intercept[MapmError](HarnessStats.parse(t, "s.json")).getMessage
    assert(error(text.replace("\"cycles\": 123456,", "")) == "s.json: the harness stats lack 'cycles'")
    assert(error(text.replace("\"hitRate\": 0.75", "\"rate\": 0.75")) == "s.json: the harness stats lack 'caches.tsL1.hitRate'")
    assert(error(text.replace("\"seed\": 7", "\"seed\": \"7\"")) == "s.json: the harness stats' 'seed' is not a number")
    assert(error(text.replace("\"cycles\": 123456", "\"cycles\": 1.5")) == "s.json: the harness stats' 'cycles' is not a whole number: 1.5")
    assert(error(text.replace("\"counters\": {", "\"counters\": [").replace("\"rqPeak\": 9 }", "\"rqPeak\": 9 ]")).startsWith("s.json: the harness stats are not JSON"))
    assert(error("[]") == "s.json: the harness stats are not a JSON object")
    assert(error(text.replace("\"stallCycles\": {", "\"stallCycles\": 3, \"x\": {")) == "s.json: the harness stats' 'stallCycles' is not an object")
  }
}
