package mapm.util

import chisel3._

/** A rotation of a sequence of signals by a run-time amount. */
object Rotate {
  /** `v` rotated by `by` (which must be below `v.size`): element k of the result is v((k + by) mod n),
    * or v((k - by) mod n) when `back`. A barrel of log2(n) stages of n two-way selects (a rotation
    * by each set bit's weight mod n), not n n-way selects: the same function at n log n cost. */
  def apply[T <: Data](v: Seq[T], by: UInt, back: Boolean = false): Seq[T] = {
    val n = v.size
    (0 until Index.bits(n)).filter(b => ((1 << b) % n) != 0).foldLeft(v) { (cur, b) =>
      val step = if (back) n - (1 << b) % n else (1 << b) % n
      Seq.tabulate(n)(k => Mux(by(b), cur((k + step) % n), cur(k)))
    }
  }
}
