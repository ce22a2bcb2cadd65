package mapm.format

/** The MAPM's performance counters, defined once: the hardware's counter ports
  * (`mapm.params.MapmCounters`, `io_counters_<name>`), the coprocessor's register map
  * ([[RegisterMap]]: one 64-bit register pair each, in this order) and the harness's stats all
  * take these names and units. */
object CounterSet {
  /** The counters' names, in port order. `rqPeak` is the largest occupancy any TSM's Register-queue
    * bank reached (the overflow rule's witness); `tsL2_conflicts` and `sopL2_conflicts` the L1
    * misses' cycles of waiting on an L2 bank that took another L1's miss (`mapm.uncore.L2`). */
  val Names: Seq[String] = Seq("cycles", "queries", "tsOps", "soIssued", "soPassed", "stallNodeData", "stallRsFull",
    "stallRqFull", "stallQuery", "tsL1_hits", "tsL1_misses", "tsL2_hits", "tsL2_misses", "soq_hits", "soq_misses",
    "sopL1_hits", "sopL1_misses", "sopL2_hits", "sopL2_misses", "bytesFetched", "rqPeak", "sopL2_conflicts", "tsL2_conflicts")

  /** What each counter counts. The TSMs' stalls are summed over the TSMs, one per TSM and cycle
    * (TSM-cycles): with 16 TSMs `stallRsFull` can reach 16 times `cycles`. A cache's hits and
    * misses are summed over its instances (the TS L1s, the SOP L1 banks). */
  val Units: Map[String, String] = Map(
    "cycles" -> "cycles", "queries" -> "queries", "tsOps" -> "operations", "soIssued" -> "operations", "soPassed" -> "operations",
    "stallNodeData" -> "TSM-cycles", "stallRsFull" -> "TSM-cycles", "stallRqFull" -> "TSM-cycles", "stallQuery" -> "cycles",
    "bytesFetched" -> "bytes", "rqPeak" -> "entries", "sopL2_conflicts" -> "requester-cycles", "tsL2_conflicts" -> "requester-cycles") ++
    Seq("tsL1", "tsL2", "soq", "sopL1", "sopL2").flatMap(c => Seq(s"${c}_hits" -> "accesses", s"${c}_misses" -> "accesses"))
  require(Units.keySet == Names.toSet, s"every counter needs a unit: ${Names.filterNot(Units.contains)}")
}
