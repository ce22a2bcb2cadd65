package mapm.top

import chisel3._
import chisel3.util._
import mapm.params._
import mapm.memory.{MemPort, MemPortParams}
import mapm.shader.SoBlock
import mapm.tsearch.TsBlock
import mapm.uncore.{Shapes, Uncore}
import mapm.util.{CostBlock, Counters}

/** The whole Multi-Accelerator for Photon Mapping (3.2, docs/mapm.md), as wiring of three parts:
  * the Tree Search block ([[TsBlock]]: query stream, SOQ cache, Launcher, TSMs with TS L1s, TSAs,
  * Nextnode and the Register queue), the Shader Operation block ([[SoBlock]]: SOMs with
  * reservation stations, SOP L1 banks and SOAs), and the [[Uncore]] between them and memory (TS
  * L2, SOP L2, the memory arbiter that keeps at most `memory.maxOutstanding` requests in flight on
  * the one memory port, and the Data bus). Every port shape between them is [[Shapes]]'.
  *
  * The host sets `cfg` before the first query, feeds tree-search instructions on `query`, plays
  * DRAM on `mem` (read only), collects every shader operation's result on `out` (one port per
  * SOA; the results whose cond holds are the colour to add to the query's pixel), and waits for
  * `done` after its last query: every accepted query finished, nothing in flight anywhere, no
  * memory request outstanding, and the counters settled ([[Mapm.counterSettle]] cycles after the
  * MAPM fell idle; `counters` are exact from then on). `error` is sticky (a malformed node record, an invalid TSA input,
  * a cache protocol error or a Register-queue overflow; none can happen on a model-built image).
  *
  * Latency: variable (memory, stalls); a query's first SO leaves after about 3 (SOQ) + 4 + TSA +
  * 1 + 4 + SOA latency cycles on cache hits. Throughput: one tree-search operation per TSM and one
  * shader operation per SOA per cycle.
  */
class Mapm(val p: MapmParams) extends Module {
  override def desiredName = s"Mapm_${p.name}"
  CostBlock.tag(this, CostBlock.Top)
  val memParams: MemPortParams = Shapes(p).mem

  val io = IO(new Bundle {
    val cfg = Input(new MapmConfig(p))
    val query = Flipped(Decoupled(new QueryIn(p)))
    val mem = new MemPort(memParams)
    val out = Output(Vec(p.counts.som * p.counts.soaPerSom, Valid(new SoResult(p))))
    /** Results the consumer of each `out` port can still take: a lane takes new SOs only while all
      * it has fit (a consumer that always takes ties it to [[Mapm.resultRoom]]). */
    val room = Input(Vec(p.counts.som * p.counts.soaPerSom, UInt(log2Ceil(Mapm.resultRoom(p) + 1).W)))
    val done = Output(Bool())
    val error = Output(Bool())
    val counters = Output(new MapmCounters)
  })

  val ts = Module(new TsBlock(p))
  val so = Module(new SoBlock(p))
  val uncore = Module(new Uncore(p))
  ts.io.cfg := io.cfg
  so.io.cfg := io.cfg
  ts.io.query <> io.query
  io.out := so.io.out
  so.io.room := io.room

  uncore.io.tsL1 <> ts.io.l1
  uncore.io.soq <> ts.io.soq
  uncore.io.sopL1 <> so.io.l1
  uncore.io.groups <> ts.io.so
  uncore.io.free := so.io.free
  so.io.in := uncore.io.som
  io.mem <> uncore.io.mem

  // Done once idle for as long as the counters trail their events (no event happens while idle,
  // so the counters read at done are exact; mapm.util.Counters).
  private val allIdle = ts.io.idle && so.io.idle && uncore.io.idle
  private val settle = Mapm.counterSettle(p)
  private val idleFor = RegInit(0.U(log2Ceil(settle + 1).W))
  idleFor := Mux(!allIdle, 0.U, Mux(idleFor === settle.U, idleFor, idleFor + 1.U))
  io.done := allIdle && idleFor === settle.U
  val error = RegInit(false.B)
  when(ts.io.error || so.io.error || uncore.io.protocolError) { error := true.B }
  io.error := error

  val c = io.counters
  private val tc = ts.io.counters
  private val sc = so.io.counters
  private val uc = uncore.io.counters
  c.cycles := Counters.count(Seq(true.B))
  c.queries := Counters.count(Seq(io.query.fire))
  c.tsOps := tc.tsOps
  c.soIssued := sc.soIssued
  c.soPassed := sc.soPassed
  c.stallNodeData := tc.stallNodeData
  c.stallRsFull := tc.stallRsFull
  c.stallRqFull := tc.stallRqFull
  c.stallQuery := tc.stallQuery
  c.tsL1_hits := tc.tsL1Hits
  c.tsL1_misses := tc.tsL1Misses
  c.tsL2_hits := uc.tsL2.hits
  c.tsL2_misses := uc.tsL2.misses
  c.tsL2_conflicts := uc.tsL2.conflicts
  c.soq_hits := tc.soqHits
  c.soq_misses := tc.soqMisses
  c.sopL1_hits := sc.sopL1Hits
  c.sopL1_misses := sc.sopL1Misses
  c.sopL2_hits := uc.sopL2.hits
  c.sopL2_misses := uc.sopL2.misses
  c.sopL2_conflicts := uc.sopL2.conflicts
  c.bytesFetched := uc.bytesFetched
  c.rqPeak := tc.rqPeak
}

object Mapm {
  /** The cycles `done` waits after the MAPM falls idle: the longest any counter trails its events
    * (the Register-queue peak, a max over the TSMs, or an event count; a cache's hit or miss comes a
    * cycle after its lookup). */
  def counterSettle(p: MapmParams): Int =
    math.max(Counters.CountLatency + mapm.memory.ReadOnlyCache.EventLatency, Counters.maxLatency(p.counts.tsm))

  /** The room that never slows a lane: what one lane may have on its way
    * ([[mapm.shader.SomLane.resultFifo]]). */
  def resultRoom(p: MapmParams): Int = mapm.shader.SomLane.resultFifo(p)
}
