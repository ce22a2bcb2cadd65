package mapm.uncore

import chisel3._
import chisel3.util._
import chisel3.experimental.hierarchy.{Definition, Instance}
import mapm.memory.{CacheConfig, MemArbiter, MemArbiterTree, MemPort, MemPortParams, ReadOnlyCache, RegFifo}
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
  *    queue. No combinational path runs from an L1 through the network to a bank or back. The L1s
  *    sit in groups of eight ([[L2Group]]: their queues, the banks' arbiters over the group, the
  *    response merges), so the wiring between the groups and the banks grows as C/8 x n links,
  *    not C x n. `mem` has one port per bank.
  *
  * Every arbiter over more than eight L1s is a registered tree (groups of eight, a two-entry
  * queue after each group's arbiter: [[MemArbiterTree]] for the shared L2, [[L2Group]] and a
  * bank's arbiter over the groups for the banked one), so no grant decides among more than eight
  * requests in a cycle; that adds a cycle to a request from more than eight L1s.
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
  private val banks = Seq.fill(n)(Instance(bankDef))
  for (b <- 0 until n) io.mem(b) <> banks(b).io.down
  private val maxOutstanding = 4 * clients

  private val errors: Seq[Bool] = structure match {
    case L2Structure.Shared =>
      val arb = Module(new MemArbiterTree(up, clients, maxOutstanding))
      for (i <- 0 until clients) arb.io.up(i) <> io.l1(i)
      banks.head.io.up <> arb.io.down
      io.counters.conflicts := Counters.count(io.l1.map(l => l.req.valid && !l.req.ready && arb.io.down.req.fire))
      Seq(arb.io.protocolError)
    case L2Structure.Banked(_) =>
      // The L1s in groups of eight (L2Group: their queues, each bank's arbiter over the group, the
      // response merges), then each bank's arbiter over the groups: the tree MemArbiterTree builds,
      // with the links between groups and banks, not between L1s and banks.
      val members = (0 until clients).grouped(MemArbiterTree.FanIn).toSeq
      val queued = members.size > 1
      val groupDefs = members.map(_.size).distinct.map(m => m -> Definition(new L2Group(up, m, n, bank.lineBytes, maxOutstanding, queued))).toMap
      val groups = members.map(m => Instance(groupDefs(m.size)))
      lazy val outerDef = Definition(new MemArbiter(groups.map(_.io.bank(0).p), maxOutstanding))
      for ((m, g) <- members.zip(groups); (l1, i) <- m.zipWithIndex) g.io.l1(i) <> io.l1(l1)
      val took = for (k <- 0 until n) yield {
        val toBank = if (!queued) groups.head.io.bank(k) else {
          val outer = Instance(outerDef)
          for ((g, j) <- groups.zipWithIndex) outer.io.up(j) <> g.io.bank(k)
          outer.io.down
        }
        require(toBank.p == bank.up, s"the groups' tree changes the bank's port: ${toBank.p}, the bank takes ${bank.up}")
        banks(k).io.up.req <> RegFifo.registered(toBank.req)
        toBank.resp <> RegFifo.registered(banks(k).io.up.resp)
        toBank.req.fire
      }
      for (g <- groups) g.io.bankTook := VecInit(took)
      io.counters.conflicts := Counters.count(groups.flatMap(_.io.waits))
      groups.map(_.io.protocolError)
  }

  io.protocolError := (banks.map(_.io.protocolError) ++ errors).reduce(_ || _)
  io.counters.hits := Counters.count(banks.map(_.io.events.hit))
  io.counters.misses := Counters.count(banks.map(_.io.events.miss))
}
