package mapm.tsearch

import chisel3._
import chisel3.experimental.hierarchy.{Definition, Instance}
import chisel3.util._
import mapm.memory.MemPort
import mapm.params.{MapmConfig, MapmParams, QueryIn, SoGroup}
import mapm.uncore.Shapes
import mapm.util.{CostBlock, Counters, Index, RoundRobin}

/** Counters of the TS block (64 bits each; docs/mapm.md). */
class TsCounters extends Bundle {
  val tsOps = UInt(64.W)
  val stallNodeData = UInt(64.W)
  val stallRsFull = UInt(64.W)
  val stallRqFull = UInt(64.W)
  val stallQuery = UInt(64.W)
  val tsL1Hits = UInt(64.W)
  val tsL1Misses = UInt(64.W)
  val soqHits = UInt(64.W)
  val soqMisses = UInt(64.W)
  val rqPeak = UInt(64.W)
}

/** The Tree Search block (3.3): [[QueryFetch]] (the host's query stream and the SOQ cache), the
  * Launcher, and `tsm` [[Tsm]]s (each with its TS L1, TSA, Nextnode and bank of the Register
  * queue). The TS L2 below the TS L1s is the uncore's ([[mapm.uncore.Uncore]]).
  *
  * The Launcher hands the next query (in stream order) to one TSM that can start it, choosing
  * round-robin from the TSM after the last one served; a TSM takes a new query only when its
  * bank of the Register queue is empty, so pending child searches always go first (3.3). With an
  * empty tree (`nodeCount` 0) every query is accepted and finishes at once, with no operation.
  *
  * Outputs: one SO group port per TSM, each TSM's TS L1 miss port and the SOQ cache's, `idle`
  * (nothing held anywhere in the block), a sticky `error`, and the counters.
  *
  * Latency: a query's root operation enters a TSM one cycle after its SOQ record arrives.
  * Throughput: one new query per cycle, one tree-search operation per TSM per cycle.
  */
class TsBlock(p: MapmParams) extends Module {
  private val t = p.counts.tsm
  override def desiredName = s"TsBlock_t${t}_${p.numbers.format.name}"
  CostBlock.tag(this, CostBlock.TsBlock)
  private val shapes = Shapes(p)

  val io = IO(new Bundle {
    val cfg = Input(new MapmConfig(p))
    val query = Flipped(Decoupled(new QueryIn(p)))
    val so = Vec(t, Decoupled(new SoGroup(p)))
    /** Each TSM's TS L1 miss port. */
    val l1 = Vec(t, new MemPort(shapes.tsL1.down))
    /** The SOQ cache's miss port. */
    val soq = new MemPort(shapes.soq.down)
    val idle = Output(Bool())
    val error = Output(Bool())
    val counters = Output(new TsCounters)
  })

  val fetch = Module(new QueryFetch(p))
  fetch.io.queryBase := io.cfg.queryBase
  fetch.io.in <> io.query
  io.soq <> fetch.io.mem

  // Depth-first reserve: the bit length of the node count bounds the depth of the tree the model
  // builds (each split halves the photons, 3.1.4).
  private val emptyTree = io.cfg.nodeCount === 0.U
  private val reserve = Mux(emptyTree, 0.U, Log2(io.cfg.nodeCount) +& 1.U)

  val tsms: Seq[Instance[Tsm]] = { val d = Definition(new Tsm(p)); Seq.fill(t)(Instance(d)) } // elaborated once

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
    io.l1(i) <> m.io.mem
    io.so(i) <> m.io.so
  }
  fetch.io.out.ready := emptyTree || anyWilling
  when(offered && anyWilling) { last := chosen }

  io.idle := fetch.io.idle && tsms.map(_.io.idle).reduce(_ && _)
  io.error := fetch.io.error || tsms.map(_.io.error).reduce(_ || _)

  // Counters.
  import Counters.{count => counter}
  io.counters.tsOps := counter(tsms.map(_.io.events.tsOp))
  io.counters.stallNodeData := counter(tsms.map(_.io.events.stallNodeData))
  io.counters.stallRsFull := counter(tsms.map(_.io.events.stallRsFull))
  io.counters.stallRqFull := counter(tsms.map(_.io.events.stallRqFull))
  io.counters.stallQuery := counter(Seq(fetch.io.waiting && !fetch.io.out.valid && anyWilling))
  io.counters.tsL1Hits := counter(tsms.map(_.io.l1.hit))
  io.counters.tsL1Misses := counter(tsms.map(_.io.l1.miss))
  io.counters.soqHits := counter(Seq(fetch.io.soq.hit))
  io.counters.soqMisses := counter(Seq(fetch.io.soq.miss))
  io.counters.rqPeak := Counters.max(tsms.map(_.io.rqPeak))
}
