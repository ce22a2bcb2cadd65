package mapm.util

import chisel3._
import chisel3.util._

/** Event counting for the performance counters. */
object Counters {
  /** The sum of `xs`, zero-extended so it cannot overflow, as a balanced adder tree. */
  def sum(xs: Seq[UInt]): UInt =
    if (xs.isEmpty) 0.U
    else if (xs.size == 1) xs.head
    else { val (a, b) = xs.splitAt(xs.size / 2); sum(a) +& sum(b) }

  /** A 64-bit counter that adds, every cycle, how many of `events` are high. */
  def count(events: Seq[Bool]): UInt = {
    val c = RegInit(0.U(64.W))
    c := c + PopCount(events)
    c
  }
}
