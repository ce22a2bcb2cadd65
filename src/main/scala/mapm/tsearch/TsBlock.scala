package mapm.tsearch

import chisel3._
import chisel3.experimental.hierarchy.{Definition, Instance}
import chisel3.util._
import mapm.memory.{CacheConfig, MemArbiter, MemPort, ReadOnlyCache}
import mapm.params.{MapmConfig, MapmParams, QueryIn, SoGroup}
import mapm.util.{Counters, Index, RoundRobin, Rotate}

/** Counters of the TS block (64 bits each; docs/mapm.md). */
class TsCounters extends Bundle {
  val tsOps = UInt(64.W)
  val stallNodeData = UInt(64.W)
  val stallRsFull = UInt(64.W)
  val stallRqFull = UInt(64.W)
  val stallQuery = UInt(64.W)
  val tsL1Hits = UInt(64.W)
  val tsL1Misses = UInt(64.W)
  val tsL2Hits = UInt(64.W)
  val tsL2Misses = UInt(64.W)
  val soqHits = UInt(64.W)
  val soqMisses = UInt(64.W)
  val rqPeak = UInt(64.W)
}

/** The Tree Search block (3.3): [[QueryFetch]] (the host's query stream and the SOQ cache), the
  * Launcher, `tsm` [[Tsm]]s (each with its TS L1, TSA, Nextnode and bank of the Register queue),
  * and the shared TS L2 behind a [[MemArbiter]] of the L1s.
  *
  * The Launcher hands the next query (in stream order) to one TSM that can start it, choosing
  * round-robin from the TSM after the last one served; a TSM takes a new query only when its
  * bank of the Register queue is empty, so pending child searches always go first (3.3). With an
  * empty tree (`nodeCount` 0) every query is accepted and finishes at once, with no operation.
  * The TS L2 (Table 4.2: fully associative, built as 16-way with a hashed index,
  * docs/memory-port.md) serves the L1s' line fetches.
  *
  * Outputs: one SO group port per TSM, the TS L2's and the SOQ cache's memory ports, `idle`
  * (nothing held anywhere in the block), a sticky `error`, and the counters.
  *
  * Latency: a query's root operation enters a TSM one cycle after its SOQ record arrives.
  * Throughput: one new query per cycle, one tree-search operation per TSM per cycle.
  */
class TsBlock(p: MapmParams) extends Module {
  private val t = p.counts.tsm
  override def desiredName = s"TsBlock_t${t}_${p.numbers.format.name}"
  private val l1 = Tsm.l1Config(p)
  val l2Config: CacheConfig = TsBlock.l2Config(p)

  val io = IO(new Bundle {
    val cfg = Input(new MapmConfig(p))
    val query = Flipped(Decoupled(new QueryIn(p)))
    val so = Vec(t, Decoupled(new SoGroup(p)))
    val tsMem = new MemPort(l2Config.down)
    val soqMem = new MemPort(QueryFetch.soqConfig(p).down)
    val idle = Output(Bool())
    val error = Output(Bool())
    val counters = Output(new TsCounters)
  })

  val fetch = Module(new QueryFetch(p))
  fetch.io.queryBase := io.cfg.queryBase
  fetch.io.in <> io.query
  io.soqMem <> fetch.io.mem

  // Depth-first reserve: the bit length of the node count bounds the depth of the tree the model
  // builds (each split halves the photons, 3.1.4).
  private val emptyTree = io.cfg.nodeCount === 0.U
  private val reserve = Mux(emptyTree, 0.U, Log2(io.cfg.nodeCount) +& 1.U)

  val tsms: Seq[Instance[Tsm]] = { val d = Definition(new Tsm(p)); Seq.fill(t)(Instance(d)) } // elaborated once
  val arb = Module(new MemArbiter(l1.down, t, maxOutstanding = 4 * t))
  val l2 = Module(new ReadOnlyCache(l2Config))
  l2.io.up <> arb.io.down
  io.tsMem <> l2.io.down

  // Launcher: the next query to the first willing TSM after the last one served.
  val last = RegInit((t - 1).U(Index.bits(t).W))
  private val willing = VecInit(tsms.map(_.io.query.ready)).asUInt
  private val (anyWilling, chosen) = RoundRobin.first(willing, Index.next(last, t))
  private val offered = fetch.io.out.valid && !emptyTree
  for ((m, i) <- tsms.zipWithIndex) {
    m.io.cfg.h := io.cfg.h
    m.io.cfg.nodeBase := io.cfg.nodeBase
    m.io.cfg.nodeCount := io.cfg.nodeCount
    m.io.cfg.reserve := reserve
    m.io.query.valid := offered && chosen === i.U
    m.io.query.bits := fetch.io.out.bits
    m.io.queryWaiting := offered
    arb.io.up(i) <> m.io.mem
    io.so(i) <> m.io.so
  }
  fetch.io.out.ready := emptyTree || anyWilling
  when(offered && anyWilling) { last := chosen }

  io.idle := fetch.io.idle && tsms.map(_.io.idle).reduce(_ && _)
  io.error := fetch.io.error || l2.io.protocolError || arb.io.protocolError || tsms.map(_.io.error).reduce(_ || _)

  // Counters.
  import Counters.{count => counter}
  io.counters.tsOps := counter(tsms.map(_.io.events.tsOp))
  io.counters.stallNodeData := counter(tsms.map(_.io.events.stallNodeData))
  io.counters.stallRsFull := counter(tsms.map(_.io.events.stallRsFull))
  io.counters.stallRqFull := counter(tsms.map(_.io.events.stallRqFull))
  io.counters.stallQuery := counter(Seq(fetch.io.waiting && !fetch.io.out.valid && anyWilling))
  io.counters.tsL1Hits := Counters.sum(tsms.map(_.io.l1.hits))
  io.counters.tsL1Misses := Counters.sum(tsms.map(_.io.l1.misses))
  io.counters.tsL2Hits := l2.io.counters.hits
  io.counters.tsL2Misses := l2.io.counters.misses
  io.counters.soqHits := fetch.io.soq.hits
  io.counters.soqMisses := fetch.io.soq.misses
  io.counters.rqPeak := tsms.map(_.io.rqPeak).reduce((a, b) => Mux(a > b, a, b))
}

object TsBlock {
  /** The TS L2: Table 4.2's geometry, serving the L1s' lines through their arbiter, fetching from
    * memory in the port's beats. */
  def l2Config(p: MapmParams): CacheConfig =
    CacheConfig.below(MemArbiter.downParams(Seq.fill(p.counts.tsm)(Tsm.l1Config(p).down)), p.caches.tsL2,
      downBytes = p.memory.dataBytes)
}
