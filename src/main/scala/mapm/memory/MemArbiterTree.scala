package mapm.memory

import chisel3._
import chisel3.util._
import chisel3.experimental.hierarchy.{Definition, Instance, instantiable, public}

/** A [[MemArbiter]] over `n` ports of one shape, built as a registered tree when `n` is larger
  * than `fanIn`: the ports in groups of `fanIn`, each group's round-robin arbiter feeding a
  * two-entry register FIFO ([[RegFifo]]), and one round-robin arbiter over the FIFOs. No grant
  * then decides among more than `fanIn` requests in a cycle (a flat arbiter over the SOP L2's 32
  * ports set that part's clock). The shared port and its ids are the flat arbiter's: the down id is
  * the group, the port in the group and the port's own id, which is the port index above the own id
  * when `fanIn` is a power of two, as it must be; responses route back through both levels.
  *
  * Latency: a request spends one cycle in its group's FIFO (none with `n <= fanIn`); response beats
  * pass through combinationally. Throughput: one request and one response beat per cycle. Fairness:
  * round robin over the groups, and within each group over its ports.
  */
@instantiable
class MemArbiterTree(up: MemPortParams, n: Int, maxOutstanding: Int, fanIn: Int = MemArbiterTree.FanIn) extends Module {
  require(fanIn >= 2 && isPow2(fanIn), s"a memory arbiter tree's fan-in must be a power of two of at least 2, got $fanIn")
  require(n >= 1, "memory arbiter needs at least one port")
  private val groups = (0 until n).grouped(fanIn).toSeq
  private val innerDown = groups.map(g => MemArbiter.downParams(Seq.fill(g.size)(up)))
  val downParams: MemPortParams = if (n <= fanIn) MemArbiter.downParams(Seq.fill(n)(up)) else MemArbiter.downParams(innerDown)
  require(downParams == MemArbiter.downParams(Seq.fill(n)(up)), s"tree over $n ports changes the shared port: $downParams")
  override def desiredName = s"MemArbiterTree_n${n}_f${fanIn}_o$maxOutstanding"

  @public val io = IO(new Bundle {
    val up = Vec(n, Flipped(new MemPort(MemArbiterTree.this.up)))
    val down = new MemPort(downParams)
    /** Sticky: any level's protocol error ([[MemArbiter]]). */
    val protocolError = Output(Bool())
  })

  if (n <= fanIn) {
    val a = Module(new MemArbiter(up, n, maxOutstanding))
    for (i <- 0 until n) a.io.up(i) <> io.up(i)
    io.down <> a.io.down
    io.protocolError := a.io.protocolError
  } else {
    // The groups' arbiters and queues of one size are elaborated once and instantiated (a wide L2
    // has thousands of them).
    val groupDefs = groups.map(_.size).distinct.map(k => k -> Definition(new MemArbiter(up, k, maxOutstanding))).toMap
    val queueDefs = groups.map(_.size).distinct.map(k => k -> Definition(new RegFifo(new MemReq(MemArbiter.downParams(Seq.fill(k)(up))), 2))).toMap
    val inner = groups.map(g => Instance(groupDefs(g.size)))
    val outer = Module(new MemArbiter(innerDown, maxOutstanding))
    for ((g, a) <- groups.zip(inner); (i, k) <- g.zipWithIndex) a.io.up(k) <> io.up(i)
    for ((a, j) <- inner.zipWithIndex) {
      outer.io.up(j).req <> RegFifo.registered(queueDefs(groups(j).size), a.io.down.req)
      a.io.down.resp <> outer.io.up(j).resp
    }
    io.down <> outer.io.down
    io.protocolError := (outer.io.protocolError +: inner.map(_.io.protocolError)).reduce(_ || _)
  }
}

object MemArbiterTree {
  /** The default fan-in: an eight-way round robin fits the units' clock. */
  val FanIn = 8
}
