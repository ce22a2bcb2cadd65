package mapm.util

import chisel3._
import chisel3.util._

/** Combinational selection helpers shared by the TS and SO blocks. */
object Pick {
  /** The first set bit of `mask` at or after position `from`, wrapping around to the bottom:
    * (any bit set, its index). Round-robin arbiters pass `from` = one past the last grant. */
  def roundRobin(mask: UInt, from: UInt): (Bool, UInt) = {
    val n = mask.getWidth
    if (n == 1) (mask(0), 0.U(1.W))
    else {
      val above = mask & VecInit((0 until n).map(i => i.U >= from)).asUInt
      (mask.orR, Mux(above.orR, PriorityEncoder(above), PriorityEncoder(mask)))
    }
  }

  /** [[roundRobin]] as a one-hot mask (all zero when `mask` is). */
  def roundRobinOH(mask: UInt, from: UInt): UInt = {
    val n = mask.getWidth
    if (n == 1) mask
    else {
      val above = mask & VecInit((0 until n).map(i => i.U >= from)).asUInt
      Mux(above.orR, PriorityEncoderOH(above), PriorityEncoderOH(mask))
    }
  }

  /** `i + 1` modulo `n` for an index register of `log2Ceil(n)` bits (at least one bit). */
  def next(i: UInt, n: Int): UInt = if (n == 1) 0.U else Mux(i === (n - 1).U, 0.U, i + 1.U)

  /** Width of an index into `n` things (at least one bit). */
  def bits(n: Int): Int = log2Ceil(n) max 1

  /** The sum of `xs`, zero-extended so it cannot overflow, as a balanced adder tree. */
  def sum(xs: Seq[UInt]): UInt =
    if (xs.isEmpty) 0.U
    else if (xs.size == 1) xs.head
    else { val (a, b) = xs.splitAt(xs.size / 2); sum(a) +& sum(b) }

  /** A 64-bit counter that adds, every cycle, how many of `events` are high. */
  def counter(events: Seq[Bool]): UInt = {
    val c = RegInit(0.U(64.W))
    c := c + PopCount(events)
    c
  }
}
