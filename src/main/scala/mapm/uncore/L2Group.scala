package mapm.uncore

import chisel3._
import chisel3.util._
import chisel3.experimental.hierarchy.{Definition, Instance, instantiable, public}
import mapm.memory.{MemArbiter, MemPort, MemPortParams, MemReq, MemResp, RegFifo}

/** The L1 side of a banked [[L2]]'s network for one group of up to eight L1s: each L1's request
  * enters a two-entry queue and goes, by its line address's bank bits, to that bank's round-robin
  * arbiter over the group; each arbiter's winner leaves for its bank through a two-entry queue
  * (`queued`; without it, when the whole L2 has one group, straight). Each bank's response beats
  * come back on the bank's link, route to their L1 by id, meet the other banks' beats for that L1 in
  * a round-robin arbiter and leave through a two-entry queue. A bank's arbiter over the groups
  * ([[L2]]) completes the tree that [[mapm.memory.MemArbiterTree]] builds for a shared L2, so the
  * grants, ids and cycles are a tree's; what changes is the wiring: an L2 of C L1s and B banks has
  * C/8 x B links between the groups and the banks, not C x B.
  *
  * Latency: a request spends a cycle in its L1's queue and one in its bank link's queue (when
  * `queued`); a response beat a cycle in its L1's queue. Throughput: one request a cycle per L1 and
  * per bank link, one response beat a cycle per L1.
  *
  * @param members        the L1s of the group (1 to 8)
  * @param banks          the L2's banks
  * @param lineBytes      the bank's line, whose address bits above it choose the bank
  * @param maxOutstanding requests in flight on one bank link
  */
@instantiable
class L2Group(up: MemPortParams, members: Int, banks: Int, lineBytes: Int, maxOutstanding: Int, queued: Boolean) extends Module {
  require(members >= 1 && members <= 8, s"an L2 group serves 1 to 8 L1s, got $members")
  require(banks >= 2 && isPow2(banks), s"an L2 group needs a power of two of at least 2 banks, got $banks")
  override def desiredName = s"L2Group_m${members}_b${banks}${if (queued) "" else "_direct"}"
  val linkParams: MemPortParams = MemArbiter.downParams(Seq.fill(members)(up))

  @public val io = IO(new Bundle {
    val l1 = Vec(members, Flipped(new MemPort(up)))
    /** One link to each bank's arbiter over the groups. */
    val bank = Vec(banks, new MemPort(linkParams))
    /** Each bank's arbiter took a request this cycle (for `waits`). */
    val bankTook = Input(Vec(banks, Bool()))
    /** Each L1's request waited because its bank took another request this cycle. */
    val waits = Output(Vec(members, Bool()))
    /** Sticky: a protocol error in any of the group's arbiters ([[MemArbiter]]). */
    val protocolError = Output(Bool())
  })

  private val reqQ = Definition(new RegFifo(new MemReq(up), 2))
  private val respQ = Definition(new RegFifo(new MemResp(up), 2))
  private lazy val linkQ = Definition(new RegFifo(new MemReq(linkParams), 2)) // only when `queued`: an unused definition's reset is never inferred
  private val arbDef = Definition(new MemArbiter(up, members, maxOutstanding))
  private val arbs = Seq.fill(banks)(Instance(arbDef))
  private val respArbDef = Definition(new RespArbiter(up, banks))

  private val bankBits = log2Ceil(banks)
  private val lineBits = log2Ceil(lineBytes)
  for (i <- 0 until members) {
    val req = RegFifo.registered(reqQ, io.l1(i).req)
    val b = req.bits.addr(lineBits + bankBits - 1, lineBits)
    for (k <- 0 until banks) {
      val port = arbs(k).io.up(i)
      port.req.valid := req.valid && b === k.U
      port.req.bits := req.bits
    }
    req.ready := VecInit(arbs.map(_.io.up(i).req.ready))(b)
    io.waits(i) := req.valid && !req.ready && io.bankTook(b)
    val merge = Instance(respArbDef)
    for (k <- 0 until banks) merge.io.in(k) <> arbs(k).io.up(i).resp
    io.l1(i).resp <> RegFifo.registered(respQ, merge.io.out)
  }
  for (k <- 0 until banks) {
    io.bank(k).req <> (if (queued) RegFifo.registered(linkQ, arbs(k).io.down.req) else arbs(k).io.down.req)
    arbs(k).io.down.resp <> io.bank(k).resp
  }
  io.protocolError := arbs.map(_.io.protocolError).reduce(_ || _)
}

/** The round-robin merge of `n` banks' response beats for one L1 (Chisel's `RRArbiter`), as a
  * module of its own that an L2 elaborates once. Latency: none. Throughput: one beat per cycle. */
@instantiable
class RespArbiter(up: MemPortParams, n: Int) extends Module {
  override def desiredName = s"RespArbiter_n$n"
  @public val io = IO(new ArbiterIO(new MemResp(up), n))
  private val a = Module(new RRArbiter(new MemResp(up), n))
  io <> a.io
}
