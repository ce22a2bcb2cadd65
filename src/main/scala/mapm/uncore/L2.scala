package mapm.uncore

import chisel3._
import chisel3.util._
import chisel3.experimental.hierarchy.{Definition, Instance, instantiable, public}
import mapm.memory.{CacheConfig, MemArbiterTree, MemPort, MemPortParams, MemResp, ReadOnlyCache, RegFifo}
import mapm.params.L2Structure
import mapm.util.Counters

/** Counters of an L2 (64 bits each). `conflicts` counts requester-cycles in which an L1's miss
  * waited at its L2 bank (at the shared arbiter, when shared) because the bank took another L1's
  * miss that cycle. */
class L2Counters extends Bundle {
  val hits = UInt(64.W)
  val misses = UInt(64.W)
  val conflicts = UInt(64.W)
}

/** A second-level cache shared by `clients` L1s (the TS L2 under the TSMs' L1s, the SOP L2 under
  * the SOP L1 banks, 3.2), built as `structure` says:
  *
  *  - [[L2Structure.Shared]] (Table 4.2's): one arbiter over every L1's miss port in front of
  *    one [[ReadOnlyCache]], which takes one request a cycle. `mem` has one port.
  *  - [[L2Structure.Banked]]`(n)`: `n` caches of 1/n of the capacity each, line address mod n
  *    choosing the bank, behind a network whose every path is registered (two-entry
  *    [[RegFifo]]s): each L1's request enters a two-entry queue, goes to its bank's arbiter
  *    (round robin over the L1s), and enters the bank through another two-entry queue; each bank's
  *    responses leave through a two-entry queue, route back to their L1 by id, meet the other
  *    banks' responses for that L1 in a round-robin arbiter and leave through a last two-entry
  *    queue. No combinational path runs from an L1 through the network to a bank or back. `mem`
  *    has one port per bank.
  *
  * Every arbiter over more than eight L1s is a registered tree ([[MemArbiterTree]]: groups of
  * eight, a two-entry queue after each group's arbiter), so no grant decides among more than
  * eight requests in a cycle; that adds a cycle to a request from more than eight L1s.
  *
  * Latency: a hit answers in the shared structure 3 cycles after the arbiter takes the request
  * (the cache's own latency), in the banked one 4 cycles later (a register each way on each side
  * of the arbiters). Throughput: one request a cycle shared; up to one a cycle per bank banked,
  * with `conflicts` counting the requests that waited on a busy bank.
  *
  * @param what    the L2's name in module names (`ts`, `sop`)
  * @param clients the L1s it serves
  * @param up      the shape of an L1's miss port
  * @param bank    one bank ([[Shapes.tsL2]], [[Shapes.sopL2]]; the whole cache when shared)
  */
class L2(what: String, clients: Int, up: MemPortParams, val bank: CacheConfig, val structure: L2Structure) extends Module {
  private val n = structure.banks
  require(bank.interleave == n, s"an L2 of $n banks needs banks interleaved by $n, got ${bank.interleave}")
  override def desiredName = s"L2_${what}_${structure.name}_c$clients"

  val io = IO(new Bundle {
    val l1 = Vec(clients, Flipped(new MemPort(up)))
    val mem = Vec(n, new MemPort(bank.down))
    val protocolError = Output(Bool())
    val counters = Output(new L2Counters)
  })

  // Every repeated part is elaborated once and instantiated: a wide L2 has thousands.
  private val bankDef = Definition(new ReadOnlyCache(bank))
  private val arbDef = Definition(new MemArbiterTree(up, clients, maxOutstanding = 4 * clients))
  private val banks = Seq.fill(n)(Instance(bankDef))
  private val arbs = Seq.fill(n)(Instance(arbDef))
  private val fifoDefs = scala.collection.mutable.Map.empty[String, Definition[RegFifo[Data]]]

  /** `in` through a two-entry register FIFO: valid, bits and ready all leave a register. */
  private def registered[T <: Data](in: DecoupledIO[T]): DecoupledIO[T] = {
    val gen = chiselTypeOf(in.bits)
    val key = gen match {
      case r: Record => r.getClass.getName + r.elements.map { case (k, v) => s"$k:${v.getWidth}" }.mkString(",")
      case d => d.getClass.getName + d.getWidth
    }
    val d = fifoDefs.getOrElseUpdate(key, Definition(new RegFifo[Data](gen, 2)))
    val f = Instance(d)
    f.io.enq <> in
    f.io.deq.asInstanceOf[DecoupledIO[T]]
  }
  for (b <- 0 until n) io.mem(b) <> banks(b).io.down

  structure match {
    case L2Structure.Shared =>
      for (i <- 0 until clients) arbs.head.io.up(i) <> io.l1(i)
      banks.head.io.up <> arbs.head.io.down
      io.counters.conflicts := Counters.count(io.l1.map(l => l.req.valid && !l.req.ready && arbs.head.io.down.req.fire))
    case L2Structure.Banked(_) =>
      lazy val respArbDef = Definition(new RespArbiter(up, n))
      val bankBits = log2Ceil(n)
      val lineBits = log2Ceil(bank.lineBytes)
      val waits = for (i <- 0 until clients) yield {
        val req = registered(io.l1(i).req)
        val b = req.bits.addr(lineBits + bankBits - 1, lineBits)
        for (k <- 0 until n) {
          val port = arbs(k).io.up(i)
          port.req.valid := req.valid && b === k.U
          port.req.bits := req.bits
        }
        req.ready := VecInit(arbs.map(_.io.up(i).req.ready))(b)
        val respArb = Instance(respArbDef)
        for (k <- 0 until n) respArb.io.in(k) <> arbs(k).io.up(i).resp
        io.l1(i).resp <> registered(respArb.io.out)
        req.valid && !req.ready && VecInit(arbs.map(_.io.down.req.fire))(b)
      }
      for (k <- 0 until n) {
        banks(k).io.up.req <> registered(arbs(k).io.down.req)
        arbs(k).io.down.resp <> registered(banks(k).io.up.resp)
      }
      io.counters.conflicts := Counters.count(waits)
  }

  io.protocolError := (banks.map(_.io.protocolError) ++ arbs.map(_.io.protocolError)).reduce(_ || _)
  io.counters.hits := Counters.count(banks.map(_.io.events.hit))
  io.counters.misses := Counters.count(banks.map(_.io.events.miss))
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
