package mapm.util

import chisel3._

/** A rotation of a sequence of signals by a run-time amount. */
object Rotate {
  /** `v` rotated by `by` (which must be below `v.size`): element k of the result is v((k + by) mod n),
    * or v((k - by) mod n) when `back`. A barrel of log2(n) stages of n two-way selects (a rotation
    * by each set bit's weight mod n), not n n-way selects: the same function at n log n cost. */
  def apply[T <: Data](v: Seq[T], by: UInt, back: Boolean = false): Seq[T] =
    levels(v.size).foldLeft(v)((cur, b) => level(cur, by(b), b, back))

  /** The bits of the amount a rotation of `n` things has a level for (a weight that is not a
    * multiple of n), in the order [[apply]] takes them. The levels commute, so a pipelined rotation
    * may take them in this order with registers between any two. */
  def levels(n: Int): Seq[Int] = (0 until Index.bits(n)).filter(b => ((1 << b) % n) != 0)

  /** One level: `cur` rotated by (1 << b) mod n when `on` (bit `b` of the amount) is set, else as it is. */
  def level[T <: Data](cur: Seq[T], on: => Bool, b: Int, back: Boolean): Seq[T] = {
    val n = cur.size
    val step = if (back) n - (1 << b) % n else (1 << b) % n
    Seq.tabulate(n)(k => Mux(on, cur((k + step) % n), cur(k)))
  }
}
