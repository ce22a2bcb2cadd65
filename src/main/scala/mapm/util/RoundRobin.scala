package mapm.util

import chisel3._
import chisel3.util._

/** Round-robin choice among requesters (combinational): the first set bit of a mask at or after a
  * start position, wrapping around to the bottom. Round-robin arbiters start one past their last
  * grant. */
object RoundRobin {
  /** The first set bit of `mask` at or after position `from`: (any bit set, its index). */
  def first(mask: UInt, from: UInt): (Bool, UInt) = {
    val n = mask.getWidth
    if (n == 1) (mask(0), 0.U(1.W))
    else {
      val above = mask & atOrAfter(from, n)
      (mask.orR, Mux(above.orR, PriorityEncoder(above), PriorityEncoder(mask)))
    }
  }

  /** [[first]] as a one-hot mask (all zero when `mask` is), given `after` = `atOrAfter(from, n)`,
    * which many choices from the same start share. */
  def firstOneHot(mask: UInt, after: UInt): UInt =
    if (mask.getWidth == 1) mask
    else {
      val above = mask & after
      Mux(above.orR, PriorityEncoderOH(above), PriorityEncoderOH(mask))
    }

  /** The n-bit mask of the positions at or after `from`. */
  def atOrAfter(from: UInt, n: Int): UInt = VecInit((0 until n).map(i => i.U >= from)).asUInt
}
