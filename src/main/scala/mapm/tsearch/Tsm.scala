package mapm.tsearch

import chisel3._
import chisel3.experimental.hierarchy.{instantiable, public}
import chisel3.util._
import mapm.fpu.FpuDepth
import mapm.memory.{CacheConfig, CacheEvents, MemPort, ReadOnlyCache}
import mapm.params.{MapmParams, NodeRecord, QueryData, Records, SoGroup}
import mapm.uncore.Shapes
import mapm.util.{Index, RoundRobin}

/** A pending search inside one TSM: the query's slot in the TSM's query table and the node. */
class TsmOp(p: MapmParams) extends Bundle {
  val qid = UInt(Index.bits(p.queues.tsmQueries).W)
  val node = UInt(p.indices.nodeBits.W)
}

/** What Nextnode needs of an operation besides TC_L and TC_R; it travels through the TSA as its tag. */
class NextnodeInfo(p: MapmParams) extends Bundle {
  val qid = UInt(Index.bits(p.queues.tsmQueries).W)
  val node = UInt(p.indices.nodeBits.W)
  val hasL = Bool()
  val hasR = Bool()
  val leafL = Bool()
  val leafR = Bool()
  val right = UInt(p.indices.nodeBits.W)
  /** The node record was malformed (axis 3, or a child index beyond the tree). */
  val bad = Bool()
}

/** Run-time settings of a TSM, from the top's configuration. */
class TsmConfig(p: MapmParams) extends Bundle {
  val h = UInt(p.numbers.format.width.W)
  val nodeBase = UInt(p.memory.addressBits.W)
  val nodeCount = UInt((p.indices.nodeBits + 1).W)
  /** Entries of the Register-queue bank kept back for depth-first progress (docs/mapm.md). */
  val reserve = UInt(log2Ceil(p.indices.nodeBits + 2).W)
}

/** What a TSM did this cycle, for the block's counters. */
class TsmEvents extends Bundle {
  val tsOp = Bool()
  val stallNodeData = Bool()
  val stallRsFull = Bool()
  val stallRqFull = Bool()
}

/** Tree Search Module (3.3): one search engine of the TS block, with its TS L1, its bank of the
  * Register queue, its query table, a non-blocking node-fetch window, a stallable tree-search
  * unit (the online [[TSA]], or the conventional [[ConvTSA]]: the same decisions) and Nextnode.
  *
  * Each cycle it takes at most one operation: the top of its own Register-queue bank, or (when the
  * bank is empty) a new query from the Launcher, which gets a query-table slot and starts at node
  * 0. Taking one needs a free fetch slot, the TS L1 ready, and the Register-queue rule: with `a`
  * entries in the bank, `R` entries reserved for the children of the operations in flight (2 each
  * until its node record is known, then its number of non-leaf children) and depth reserve `K`, a
  * pop needs a + R + 1 + K <= D or no operation in flight, a new query a + R + 2 + K <= D
  * (docs/mapm.md proves that the bank never overflows and the search never deadlocks).
  * The operation's node record (8 bytes) is read through the TS L1 at once; operations whose
  * record has arrived enter the TSA (round-robin), the others wait in their fetch slot (stall
  * cause "node data": a TSA bubble while records are outstanding). The TSA compares the query
  * coordinate on the node's axis with h and the split value; Nextnode then pushes the non-leaf
  * children it must visit into the bank and hands the SOs (leaf children, and the node itself when
  * TC_L and TC_R both hold) to the Data bus as one [[SoGroup]] through the output register. While
  * that register holds a group the Data bus has not taken, the whole pipeline stalls (stall cause
  * "RS full"); the fetch window keeps receiving records meanwhile.
  *
  * Latency (no stalls, L1 hit): 3 (node fetch) + 1 (issue) + TSA latency (manWidth + 7 online,
  * the adders' stages + 1 conventional) + 1
  * (output register) cycles from taking an operation to its SO group; its children can be taken
  * again the cycle after. Throughput: one tree-search operation per cycle.
  */
@instantiable
class Tsm(p: MapmParams) extends Module {
  private val fmt = p.numbers.format
  private val w = fmt.width
  private val records = p.records
  private val nq = p.queues.tsmQueries
  private val ns = p.queues.fetchSlots
  private val depth = p.queues.registerQueueDepth
  val l1Config: CacheConfig = Shapes(p).tsL1
  override def desiredName = s"Tsm_${fmt.name}_d${depth}_f${ns}_q$nq"

  @public val io = IO(new Bundle {
    val cfg = Input(new TsmConfig(p))
    /** A new query offered by the Launcher; `ready` says this TSM would take one. */
    val query = Flipped(Decoupled(new QueryData(p)))
    /** The Launcher has a query ready (for the stall counter only). */
    val queryWaiting = Input(Bool())
    val mem = new MemPort(l1Config.down)
    val so = Decoupled(new SoGroup(p))
    val idle = Output(Bool())
    val error = Output(Bool())
    val events = Output(new TsmEvents)
    val l1 = Output(new CacheEvents)
    val rqPeak = Output(UInt(log2Ceil(depth + 1).W))
  })

  val l1 = Module(new ReadOnlyCache(l1Config))
  io.mem <> l1.io.down
  io.l1 := l1.io.events
  val stack = Module(new RegisterStack(new TsmOp(p), depth))
  io.rqPeak := stack.io.peak
  private val infoWidth = (new NextnodeInfo(p)).getWidth
  val tsa: TsaUnit = Module(TsaUnit(fmt, infoWidth, stallable = true, p.numbers.arith, FpuDepth.of(fmt, p.numbers.fpuStageWeight).add))

  // Query table: a slot is in use while its reference count (operations in the bank or in flight) is non-zero.
  val table = Reg(Vec(nq, new QueryData(p)))
  val refs = RegInit(VecInit(Seq.fill(nq)(0.U(log2Ceil(depth + ns + tsa.latency + 2).W))))
  private val freeQ = VecInit(refs.map(_ === 0.U)).asUInt
  private val freeQIdx = PriorityEncoder(freeQ)

  // Fetch window.
  val slotValid = RegInit(VecInit(Seq.fill(ns)(false.B)))
  val slotReady = RegInit(VecInit(Seq.fill(ns)(false.B)))
  val slotOp = Reg(Vec(ns, new TsmOp(p)))
  val slotRec = Reg(Vec(ns, UInt((8 * records.node.bytes).W)))
  private val freeSlots = ~slotValid.asUInt
  private val freeSlot = PriorityEncoder(freeSlots)

  // Operations taken and not yet through Nextnode, and the bank entries reserved for the children
  // they may still push: 2 until the node record is known, then its non-leaf children.
  val inFlight = RegInit(0.U(log2Ceil(ns + tsa.latency + 2).W))
  val reserved = RegInit(0.U(log2Ceil(2 * (ns + tsa.latency) + 3).W))

  // Intake: the bank first, else a new query, under the Register-queue rule.
  private val canTake = freeSlots.orR && l1.io.up.req.ready
  private val load = stack.io.count +& reserved +& io.cfg.reserve
  private val popOk = stack.io.top.valid && (load + 1.U <= depth.U || inFlight === 0.U)
  private val queryOk = !stack.io.top.valid && freeQ.orR && load + 2.U <= depth.U
  private val pop = canTake && popOk
  io.query.ready := canTake && queryOk
  private val newQuery = io.query.fire
  private val take = pop || newQuery
  private val op = Wire(new TsmOp(p))
  op := stack.io.top.bits
  when(!pop) { op.qid := freeQIdx; op.node := 0.U }
  stack.io.pop := pop
  when(newQuery) { table(freeQIdx) := io.query.bits }

  l1.io.up.req.valid := take
  l1.io.up.req.bits.addr := io.cfg.nodeBase + (op.node << Records.indexShift(records.node))
  l1.io.up.req.bits.id := freeSlot
  l1.io.up.req.bits.len := 0.U
  when(take) {
    slotValid(freeSlot) := true.B
    slotReady(freeSlot) := false.B
    slotOp(freeSlot) := op
  }
  l1.io.up.resp.ready := true.B
  // When its node record arrives, a slot also keeps the query coordinate the TSA compares (by the
  // record's axis) and whether the record is malformed, so that issue only selects among slots.
  val slotP = Reg(Vec(ns, UInt(w.W)))
  val slotBad = Reg(Vec(ns, Bool()))
  when(l1.io.up.resp.fire) {
    val id = l1.io.up.resp.bits.id
    val r = l1.io.up.resp.bits.data.asTypeOf(new NodeRecord(records.slot, w))
    val qd = table(slotOp(id).qid)
    slotReady(id) := true.B
    slotRec(id) := l1.io.up.resp.bits.data
    slotP(id) := MuxLookup(r.word.axis, qd.z)(Seq(0.U -> qd.x, 1.U -> qd.y))
    slotBad(id) := r.word.axis === 3.U || (r.word.hasLeft && slotOp(id).node +& 1.U >= io.cfg.nodeCount) ||
      (r.word.hasRight && r.word.right >= io.cfg.nodeCount) || r.word.right >= (BigInt(1) << p.indices.nodeBits).U
  }

  // Issue into the TSA while the pipeline moves.
  val outValid = RegInit(false.B)
  val outBits = Reg(new SoGroup(p))
  private val en = !outValid || io.so.ready
  tsa.io.en.get := en
  private val readyMask = (slotValid.asUInt & slotReady.asUInt)
  val rrNext = RegInit(0.U(Index.bits(ns).W))
  private val (anyReady, pick) = RoundRobin.first(readyMask, rrNext)
  private val issue = en && anyReady
  when(issue) { slotValid(pick) := false.B; rrNext := Index.next(pick, ns) }
  private val rec = slotRec(pick).asTypeOf(new NodeRecord(records.slot, w))
  private val iop = slotOp(pick)
  private val word = rec.word
  tsa.io.in.valid := issue
  tsa.io.in.bits.p := slotP(pick)
  tsa.io.in.bits.h := io.cfg.h
  tsa.io.in.bits.s := rec.split.value
  private val info = Wire(new NextnodeInfo(p))
  info.qid := iop.qid
  info.node := iop.node
  info.hasL := word.hasLeft
  info.hasR := word.hasRight
  info.leafL := word.leftIsLeaf
  info.leafR := word.rightIsLeaf
  info.right := word.right(p.indices.nodeBits - 1, 0)
  info.bad := slotBad(pick)
  tsa.io.in.bits.tag := info.asUInt

  // Nextnode at the TSA's output.
  private val done = tsa.io.out.valid && en
  private val o = tsa.io.out.bits.tag.asTypeOf(new NextnodeInfo(p))
  private val (tcl, tcr) = (tsa.io.out.bits.tcl, tsa.io.out.bits.tcr)
  private val children = Seq((tcl && o.hasL && !o.leafL, o.node + 1.U), (tcr && o.hasR && !o.leafR, o.right))
  for (((go, node), k) <- children.zipWithIndex) {
    stack.io.push(k).valid := done && go
    stack.io.push(k).bits.qid := o.qid
    stack.io.push(k).bits.node := node
  }
  private val sos = Seq((tcl && o.hasL && o.leafL, o.node + 1.U), (tcr && o.hasR && o.leafR, o.right), (tcl && tcr, o.node))
  when(en) {
    outValid := done && sos.map(_._1).reduce(_ || _)
    outBits.query := table(o.qid)
    for (((v, node), k) <- sos.zipWithIndex) { outBits.photon(k).valid := v; outBits.photon(k).bits := node }
  }
  io.so.valid := outValid
  io.so.bits := outBits

  // Reference counts: +1 for a new query's root, +children -1 for an operation through Nextnode.
  private val pushes = PopCount(children.map(_._1))
  for (i <- 0 until nq) {
    val leaving = done && o.qid === i.U
    refs(i) := refs(i) + (newQuery && freeQIdx === i.U).asUInt + Mux(leaving, pushes, 0.U) - leaving.asUInt
  }
  inFlight := inFlight + take.asUInt - done.asUInt
  private def nonLeaf(hasL: Bool, leafL: Bool, hasR: Bool, leafR: Bool): UInt = (hasL && !leafL).asUInt +& (hasR && !leafR).asUInt
  private val issuedRes = nonLeaf(info.hasL, info.leafL, info.hasR, info.leafR)
  reserved := reserved + Mux(take, 2.U, 0.U) - Mux(issue, 2.U - issuedRes, 0.U) - Mux(done, nonLeaf(o.hasL, o.leafL, o.hasR, o.leafR), 0.U)

  io.idle := inFlight === 0.U && !stack.io.top.valid && !outValid
  private val err = RegInit(false.B)
  when((done && (o.bad || tsa.io.out.bits.error)) || stack.io.overflow || l1.io.protocolError) { err := true.B }
  io.error := err
  io.events.tsOp := done
  io.events.stallNodeData := en && !anyReady && slotValid.asUInt.orR
  io.events.stallRsFull := outValid && !io.so.ready
  io.events.stallRqFull := canTake && ((stack.io.top.valid && !popOk) || (!stack.io.top.valid && io.queryWaiting && freeQ.orR && !queryOk))
}
