package mapm.top

import chisel3._
import chisel3.util._
import mapm.params._
import mapm.memory.{MemArbiter, MemPort, MemPortParams}
import mapm.shader.SoBlock
import mapm.tsearch.{QueryFetch, TsBlock}
import mapm.util.{Counters, Index, RoundRobin, Rotate}

/** The whole Multi-Accelerator for Photon Mapping (3.2, docs/mapm.md): the Tree Search block
  * ([[TsBlock]]: query stream, SOQ cache, Launcher, TSMs with TS L1s, TSAs, Nextnode and the
  * Register queue, TS L2), the Shader Operation block ([[SoBlock]]: Data bus, SOMs with
  * reservation stations, SOP L1 banks and SOAs, SOP L2), and one memory port shared by the TS L2,
  * the SOQ cache and the SOP L2 through a [[MemArbiter]] that keeps at most
  * `memory.maxOutstanding` requests in flight.
  *
  * The host sets `cfg` before the first query, feeds tree-search instructions on `query`, plays
  * DRAM on `mem` (read only), collects every shader operation's result on `out` (one port per
  * SOA; the results whose cond holds are the colour to add to the query's pixel), and waits for
  * `done` after its last query: every accepted query finished, nothing in flight anywhere, no
  * memory request outstanding. `error` is sticky (a malformed node record, an invalid TSA input,
  * a cache protocol error or a Register-queue overflow; none can happen on a model-built image).
  *
  * Latency: variable (memory, stalls); a query's first SO leaves after about 3 (SOQ) + 4 + TSA +
  * 1 + 4 + SOA latency cycles on cache hits. Throughput: one tree-search operation per TSM and one
  * shader operation per SOA per cycle.
  */
class Mapm(val p: MapmParams) extends Module {
  override def desiredName = s"Mapm_${p.name}"
  val memParams: MemPortParams = Mapm.memParams(p)

  val io = IO(new Bundle {
    val cfg = Input(new MapmConfig(p))
    val query = Flipped(Decoupled(new QueryIn(p)))
    val mem = new MemPort(memParams)
    val out = Output(Vec(p.counts.som * p.counts.soaPerSom, Valid(new SoResult(p))))
    val done = Output(Bool())
    val error = Output(Bool())
    val counters = Output(new MapmCounters)
  })

  val ts = Module(new TsBlock(p))
  val so = Module(new SoBlock(p))
  ts.io.cfg := io.cfg
  so.io.cfg := io.cfg
  ts.io.query <> io.query
  so.io.in <> ts.io.so
  io.out := so.io.out

  val arb = Module(new MemArbiter(Seq(ts.io.tsMem.p, ts.io.soqMem.p) ++ so.io.mem.map(_.p), p.memory.maxOutstanding))
  arb.io.up(0) <> ts.io.tsMem
  arb.io.up(1) <> ts.io.soqMem
  for ((m, b) <- so.io.mem.zipWithIndex) arb.io.up(2 + b) <> m
  io.mem <> arb.io.down

  // Requests outstanding on the memory port (request taken to last beat).
  val outstanding = RegInit(0.U(log2Ceil(p.memory.maxOutstanding + 1).W))
  outstanding := outstanding + io.mem.req.fire.asUInt - (io.mem.resp.fire && io.mem.resp.bits.last).asUInt
  io.done := ts.io.idle && so.io.idle && outstanding === 0.U
  val error = RegInit(false.B)
  when(ts.io.error || so.io.error || arb.io.protocolError) { error := true.B }
  io.error := error

  val c = io.counters
  private val tc = ts.io.counters
  private val sc = so.io.counters
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
  c.tsL2_hits := tc.tsL2Hits
  c.tsL2_misses := tc.tsL2Misses
  c.soq_hits := tc.soqHits
  c.soq_misses := tc.soqMisses
  c.sopL1_hits := sc.sopL1Hits
  c.sopL1_misses := sc.sopL1Misses
  c.sopL2_hits := sc.sopL2Hits
  c.sopL2_misses := sc.sopL2Misses
  c.sopL2_conflicts := sc.sopL2Conflicts
  c.bytesFetched := (Counters.count(Seq(io.mem.resp.fire)) << log2Ceil(p.memory.dataBytes))(63, 0)
  c.rqPeak := tc.rqPeak
}

object Mapm {
  /** The shape of the top's memory port: the outer arbiter's shared port over the TS L2, the SOQ
    * cache and the SOP L2. */
  def memParams(p: MapmParams): MemPortParams =
    MemArbiter.downParams(Seq(TsBlock.l2Config(p).down, QueryFetch.soqConfig(p).down) ++ Seq.fill(p.uncore.sopL2.banks)(SoBlock.l2Config(p).down))
}
