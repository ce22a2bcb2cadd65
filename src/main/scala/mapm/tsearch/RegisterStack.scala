package mapm.tsearch

import chisel3._
import chisel3.util._

/** One TSM's bank of the Register queue: a last-in first-out stack of pending child searches
  * (docs/mapm.md, "Register queue rule", explains why the banks are stacks).
  *
  * Each cycle it takes up to two pushes (a tree-search operation's left and right children) and
  * one pop, which removes the entry shown on `top`. A pop and pushes in the same cycle are
  * allowed: the pop takes the entry that was on top before the pushes. Pushes never wait; the
  * owner's reservation rule guarantees room, and a push beyond `depth` raises the sticky `overflow`
  * instead of being written (it cannot happen while the rule holds; the flag makes a violation
  * visible). `peak` is the largest occupancy reached.
  *
  * Latency: a pushed entry can be popped the next cycle. Throughput: two pushes and one pop per
  * cycle.
  */
class RegisterStack[T <: Data](gen: T, val depth: Int) extends Module {
  require(depth >= 2, s"Register-queue bank needs at least 2 entries, got $depth")
  override def desiredName = s"RegisterStack_d$depth"
  private val cntBits = log2Ceil(depth + 1)
  private val idxBits = log2Ceil(depth)

  val io = IO(new Bundle {
    val push = Input(Vec(2, Valid(gen)))
    /** Remove the top entry (only while `top.valid`). */
    val pop = Input(Bool())
    val top = Output(Valid(gen))
    val count = Output(UInt(cntBits.W))
    val peak = Output(UInt(cntBits.W))
    val overflow = Output(Bool())
  })

  val slots = Reg(Vec(depth, gen))
  val count = RegInit(0.U(cntBits.W))
  val peak = RegInit(0.U(cntBits.W))
  val overflow = RegInit(false.B)

  io.top.valid := count =/= 0.U
  io.top.bits := slots((count - 1.U)(idxBits - 1, 0))
  private val popped = io.pop && io.top.valid
  private val base = count - popped.asUInt
  // Push k goes to base + (number of valid pushes before it).
  private val at = Seq(base, base + io.push(0).valid.asUInt)
  for (k <- 0 until 2) when(io.push(k).valid && at(k) < depth.U) { slots(at(k)(idxBits - 1, 0)) := io.push(k).bits }
  private val pushes = PopCount(io.push.map(_.valid))
  private val wanted = base +& pushes
  when(wanted > depth.U) { overflow := true.B }
  private val next = Mux(wanted > depth.U, depth.U, wanted)
  count := next
  when(next > peak) { peak := next }
  io.count := count
  io.peak := peak
  io.overflow := overflow
}
