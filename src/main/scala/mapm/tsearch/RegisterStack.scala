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
  require(depth >= 4, s"Register-queue bank needs at least 4 entries, got $depth")
  override def desiredName = s"RegisterStack_d$depth"
  private val cntBits = log2Ceil(depth + 1)
  private val idxBits = log2Ceil(depth)
  private val bankBits = log2Ceil(RegisterStack.bankDepth(depth))

  val io = IO(new Bundle {
    val push = Input(Vec(2, Valid(gen)))
    /** Remove the top entry (only while `top.valid`). */
    val pop = Input(Bool())
    val top = Output(Valid(gen))
    val count = Output(UInt(cntBits.W))
    val peak = Output(UInt(cntBits.W))
    val overflow = Output(Bool())
  })

  // The entries live in two register files, even and odd indices, each with one write and one
  // read port: a cycle's two pushes go to consecutive indices, so each bank takes at most one.
  // (Not a `Vec` of registers: its dynamically indexed read lowers to a packed array of every
  // entry, which Verilator rebuilds by wide concatenation every cycle, more than half of a 16/16/2
  // simulation's time.) The read is synchronous: each cycle reads the entry that will be on top
  // next cycle, and an entry pushed this cycle, which a bank cannot yet return, is bypassed.
  private val banks = Seq.fill(2)(SyncReadMem(RegisterStack.bankDepth(depth), gen))
  val count = RegInit(0.U(cntBits.W))
  val peak = RegInit(0.U(cntBits.W))
  val overflow = RegInit(false.B)

  private val popped = io.pop && io.top.valid
  private val base = count - popped.asUInt
  // Push k goes to base + (number of valid pushes before it); one beyond the depth is not written.
  private val at = Seq(base, base + io.push(0).valid.asUInt)
  private val written = Seq.tabulate(2)(k => io.push(k).valid && at(k) < depth.U)
  for ((bank, b) <- banks.zipWithIndex) {
    val hit = Seq.tabulate(2)(k => written(k) && at(k)(0) === b.U)
    when(hit(0) || hit(1)) { bank.write((Mux(hit(0), at(0), at(1)) >> 1)(bankBits - 1, 0), Mux(hit(0), io.push(0).bits, io.push(1).bits)) }
  }
  private val pushes = PopCount(io.push.map(_.valid))
  private val wanted = base +& pushes
  when(wanted > depth.U) { overflow := true.B }
  private val next = Mux(wanted > depth.U, depth.U, wanted)
  count := next
  when(next > peak) { peak := next }

  // Next cycle's top: the highest entry written this cycle if any, else the memory's entry.
  private val bypass = RegNext(written(0) || written(1), false.B)
  private val bypassData = RegEnable(Mux(written(1), io.push(1).bits, io.push(0).bits), written(0) || written(1))
  private val topAt = (next - 1.U)(idxBits - 1, 0)
  private val stored = banks.map(_.read((topAt >> 1)(bankBits - 1, 0), next =/= 0.U))
  private val odd = RegNext(topAt(0))
  io.top.valid := count =/= 0.U
  io.top.bits := Mux(bypass, bypassData, Mux(odd, stored(1), stored(0)))
  io.count := count
  io.peak := peak
  io.overflow := overflow
}

object RegisterStack {
  /** Entries of each of the two banks (even and odd indices) of a stack of `depth` entries. */
  def bankDepth(depth: Int): Int = (depth + 1) / 2
}
