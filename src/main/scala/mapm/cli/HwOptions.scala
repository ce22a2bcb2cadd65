package mapm.cli

import mainargs.{arg, main}
import mapm.pipeline.{CacheSpec, Tuning}
import mapm.params.{Hierarchy, SoBus}
import Args.{CacheSpecReader, HierarchyReader, SoBusReader}

/** The memory hierarchy and the hardware sizes Table 4.2 and the design space vary, shared by
  * `emit`, `render`, `sweep`, `evaluate` and `cost` (each takes it as one parameter; mainargs lists
  * its flags with the command's own). Every size left out keeps the hierarchy's
  * ([[mapm.pipeline.Configure.of]]). The memory's latency
  * and bandwidth belong to the harness's memory model, not to the RTL: `render`, `sweep` and
  * `evaluate` take them as `--latency` and `--bandwidth`. */
@main
final case class HwOptions(
    @arg(doc = "entries of each TSM's Register-queue bank") rqDepth: Option[Int] = None,
    @arg(doc = "reservation-station entries per SOM") rsEntries: Option[Int] = None,
    @arg(name = "ts-l1", doc = "TS L1 per TSM") tsL1: Option[CacheSpec] = None,
    @arg(name = "ts-l2", doc = "shared TS L2") tsL2: Option[CacheSpec] = None,
    @arg(doc = "SOQ query cache") soq: Option[CacheSpec] = None,
    @arg(name = "sop-l1", doc = "SOP L1 per SOM, split into one bank per SOA") sopL1: Option[CacheSpec] = None,
    @arg(name = "sop-l2", doc = "shared SOP L2") sopL2: Option[CacheSpec] = None,
    @arg(doc = "requests in flight at once on the memory port") memOutstanding: Option[Int] = None,
    @arg(doc = "memory hierarchy: scalable (the SOP L2 in banks, one per two SOP L1 banks, a 4-way SOQ and TS L1s of 64-byte lines; docs/uncore.md) or table4.2 (the dissertation's: shared L2s, a direct-mapped SOQ, and the host's query order unless --query-order says otherwise)") hierarchy: Hierarchy = Hierarchy.Scalable,
    @arg(name = "sop-l2-banks", doc = "SOP L2 banks: 1 is one shared cache with one port (Table 4.2's); 2, 4 ... 64 split it by line address, each bank with its own port, behind a registered network") sopL2Banks: Option[Int] = None,
    @arg(name = "ts-l2-banks", doc = "TS L2 banks, as --sop-l2-banks") tsL2Banks: Option[Int] = None,
    @arg(doc = "clock every SOA in every cycle, as before clock gating (for comparison)") noSoaClockGate: mainargs.Flag = mainargs.Flag(),
    @arg(doc = "clock every register inside each SOA in every cycle, as before stage gating (for comparison; docs/soa.md)") noSoaStageGate: mainargs.Flag = mainargs.Flag(),
    @arg(doc = "run the MAPM as its coprocessor (docs/coprocessor.md): it reads its queries, adds every colour into its pixel and writes the frame buffer, driven by the C driver over AXI4-Lite (render's default: see its --bare)") coproc: mainargs.Flag = mainargs.Flag(),
    @arg(name = "frame-banks", doc = "with --coproc: the frame accumulator's banks (a power of two; default one per SOA)") frameBanks: Option[Int] = None,
    @arg(name = "result-fifo", doc = "with --coproc: result FIFO entries per SOA (default the lane's RS entries + its SOA's latency + 32)") resultFifo: Option[Int] = None,
    @arg(name = "stream-lines", doc = "with --coproc: 64-byte lines of the query stream read ahead (default 4)") streamLines: Option[Int] = None,
    @arg(name = "read-stream", doc = "with --coproc: read the query stream although the host wrote the query records in the order to run, so that the stream is the identity (docs/coprocessor.md, QUERY_ORDER)") readStream: mainargs.Flag = mainargs.Flag(),
    @arg(name = "so-bus", doc = "Data bus: ring (a ring of credit tokens and a registered rotation; every stage registered) or serial (the dissertation's: SOMs claimed one TSM after another in one cycle; docs/mapm.md)") soBus: Option[SoBus] = None) {

  def tuning: Tuning = Tuning(rqDepth, rsEntries, tsL1.getOrElse(CacheSpec()), tsL2.getOrElse(CacheSpec()), soq.getOrElse(CacheSpec()),
    sopL1.getOrElse(CacheSpec()), sopL2.getOrElse(CacheSpec()), memOutstanding, !noSoaClockGate.value, sopL2Banks, tsL2Banks, hierarchy, coproc.value, frameBanks, resultFifo, streamLines, soBus,
    !noSoaStageGate.value)
}
