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

  /** [[roundRobin]] as a one-hot mask (all zero when `mask` is), given `after` = `atOrAfter(from,
    * n)`, which many picks from the same `from` share. */
  def roundRobinOH(mask: UInt, after: UInt): UInt =
    if (mask.getWidth == 1) mask
    else {
      val above = mask & after
      Mux(above.orR, PriorityEncoderOH(above), PriorityEncoderOH(mask))
    }

  /** The n-bit mask of the positions at or after `from`. */
  def atOrAfter(from: UInt, n: Int): UInt = VecInit((0 until n).map(i => i.U >= from)).asUInt

  /** `v` rotated by `by` (which must be below `v.size`): element k of the result is v((k + by) mod n),
    * or v((k - by) mod n) when `back`. A barrel of log2(n) stages of n two-way selects (a rotation
    * by each set bit's weight mod n), not n n-way selects: the same function at n log n cost. */
  def rotate[T <: Data](v: Seq[T], by: UInt, back: Boolean = false): Seq[T] = {
    val n = v.size
    (0 until bits(n)).filter(b => ((1 << b) % n) != 0).foldLeft(v) { (cur, b) =>
      val step = if (back) n - (1 << b) % n else (1 << b) % n
      Seq.tabulate(n)(k => Mux(by(b), cur((k + step) % n), cur(k)))
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
