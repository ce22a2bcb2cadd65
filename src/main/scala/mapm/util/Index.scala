package mapm.util

import chisel3._
import chisel3.util.log2Ceil

/** Indices into a set of `n` things: their width and the next one, wrapping. */
object Index {
  /** Width of an index into `n` things (at least one bit). */
  def bits(n: Int): Int = log2Ceil(n) max 1

  /** `i + 1` modulo `n` for an index register of `bits(n)` bits. */
  def next(i: UInt, n: Int): UInt = if (n == 1) 0.U else Mux(i === (n - 1).U, 0.U, i + 1.U)
}
