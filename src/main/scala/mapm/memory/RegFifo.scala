package mapm.memory

import chisel3._
import chisel3.util._
import chisel3.experimental.hierarchy.{Definition, Instance, instantiable, public}

/** A first-in first-out queue held in flip-flops, with the occupancy as an output.
  *
  * It behaves like `chisel3.util.Queue` (no pipe; flow-through when `flow`) but keeps its entries
  * in a register vector, so the emitted Verilog has no memory macro with an unused read clock
  * (which `verilator -Wall` reports for the combinational-read memory of `Queue`). `enq.ready`
  * comes from the occupancy register alone, so a queue put at a part's input registers the stall
  * path back to its sender (docs/cost.md, "Paths between parts").
  *
  * Latency: an entry enqueued in cycle t can leave in cycle t+1, or in cycle t when `flow` and
  * the queue is empty (it then passes through without being stored). Throughput: one entry in and
  * one out per cycle; `enq.ready` is low only when all `entries` are taken.
  */
@instantiable
class RegFifo[T <: Data](gen: T, entries: Int, flow: Boolean = false) extends Module {
  require(entries >= 1, s"FIFO needs at least one entry, got $entries")
  override def desiredName = s"RegFifo_$entries${if (flow) "_flow" else ""}"

  @public val io = IO(new Bundle {
    val enq = Flipped(Decoupled(gen))
    val deq = Decoupled(gen)
    val count = Output(UInt(log2Ceil(entries + 1).W))
  })

  private val ptrBits = log2Ceil(entries) max 1
  private def next(p: UInt): UInt = if (entries == 1) p else Mux(p === (entries - 1).U, 0.U, p + 1.U)
  private def at(p: UInt): T = if (entries == 1) slots(0) else slots(p)

  val slots = Reg(Vec(entries, gen))
  val head = RegInit(0.U(ptrBits.W))
  val tail = RegInit(0.U(ptrBits.W))
  val count = RegInit(0.U(log2Ceil(entries + 1).W))
  private val empty = count === 0.U

  io.enq.ready := count =/= entries.U
  io.deq.valid := !empty || (flow.B && io.enq.valid)
  io.deq.bits := (if (flow) Mux(empty, io.enq.bits, at(head)) else at(head))
  io.count := count

  // With `flow`, an entry that arrives at an empty queue and leaves at once is not stored.
  private val store = io.enq.fire && !(flow.B && empty && io.deq.ready)
  private val take = io.deq.fire && !empty
  when(store) {
    at(tail) := io.enq.bits
    tail := next(tail)
  }
  when(take) { head := next(head) }
  count := count + store.asUInt - take.asUInt
}

object RegFifo {
  /** `in` through a new two-entry [[RegFifo]]: valid, bits and ready all leave a register. */
  def registered[T <: Data](in: DecoupledIO[T]): DecoupledIO[T] = {
    val f = Module(new RegFifo(chiselTypeOf(in.bits), 2))
    f.io.enq <> in
    f.io.deq
  }

  /** `in` through an instance of `d`, a queue elaborated once for many uses. */
  def registered[T <: Data](d: Definition[RegFifo[T]], in: DecoupledIO[T]): DecoupledIO[T] = {
    val f = Instance(d)
    f.io.enq <> in
    f.io.deq
  }
}
