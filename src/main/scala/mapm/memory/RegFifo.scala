package mapm.memory

import chisel3._
import chisel3.util._

/** A first-in first-out queue held in flip-flops, with the occupancy as an output.
  *
  * It behaves like `chisel3.util.Queue` (no flow-through, no pipe) but keeps its entries in a
  * register vector, so the emitted Verilog has no memory macro with an unused read clock (which
  * `verilator -Wall` reports for the combinational-read memory of `Queue`).
  *
  * Latency: an entry enqueued in cycle t can leave in cycle t+1. Throughput: one entry in and one
  * out per cycle; `enq.ready` is low only when all `entries` are taken.
  */
class RegFifo[T <: Data](gen: T, entries: Int) extends Module {
  require(entries >= 1, s"FIFO needs at least one entry, got $entries")
  override def desiredName = s"RegFifo_$entries"

  val io = IO(new Bundle {
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

  io.enq.ready := count =/= entries.U
  io.deq.valid := count =/= 0.U
  io.deq.bits := at(head)
  io.count := count

  when(io.enq.fire) {
    at(tail) := io.enq.bits
    tail := next(tail)
  }
  when(io.deq.fire) { head := next(head) }
  count := count + io.enq.fire.asUInt - io.deq.fire.asUInt
}
