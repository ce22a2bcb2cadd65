package mapm.testutil

/** A harness `stats.json` with every field [[mapm.sim.HarnessStats]] reads, for tests of the code
  * that reads runs' results: `cycles` cycles, `so` SOs (half passing), `ts` TS ops, `bytes`
  * fetched in 32-byte requests, every cache 900 hits and 100 misses but the SOQ's `soqMisses`. */
object StatsFixture {
  def json(cycles: Long, so: Long, ts: Long, bytes: Long, soqMisses: Long): ujson.Obj = {
    val caches = Seq("tsL1", "tsL2", "soq", "sopL1", "sopL2").map(c =>
      c -> ujson.Obj("hits" -> 900, "misses" -> ujson.Num((if (c == "soq") soqMisses else 100L).toDouble), "hitRate" -> 0.9))
    ujson.Obj("top" -> "Mapm_test", "result" -> "PASS", "failure" -> ujson.Null, "seed" -> 1, "latency" -> 100,
      "latencyMax" -> 100, "queryGap" -> 0, "reqStall" -> 0, "respGap" -> 0, "bandwidthBytesPerCycle" -> 14, "clockGHz" -> 1.5,
      "cycles" -> ujson.Num(cycles.toDouble), "queries" -> 1000, "queriesCompleted" -> 1000, "soIssued" -> ujson.Num(so.toDouble),
      "soPassingCond" -> ujson.Num((so / 2).toDouble), "soPerCycle" -> so.toDouble / cycles, "tsOps" -> ujson.Num(ts.toDouble),
      "tsOpsPerCycle" -> ts.toDouble / cycles, "stallCycles" -> ujson.Obj(), "caches" -> ujson.Obj.from(caches),
      "memoryRequests" -> ujson.Num((bytes / 32).toDouble), "bytesFetched" -> ujson.Num(bytes.toDouble), "bytesPerCycle" -> bytes.toDouble / cycles,
      "gbPerSecond" -> 0, "counters" -> ujson.Obj(), "wallSeconds" -> 1, "simulatedCyclesPerSecond" -> ujson.Num(cycles.toDouble))
  }
}
