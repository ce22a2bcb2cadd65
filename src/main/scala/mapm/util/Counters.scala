package mapm.util

import chisel3._
import chisel3.util._

/** Event counting for the performance counters, built so that no counter limits the clock
  * (docs/mapm.md, "Performance counters"): no carry runs further than one segment in a cycle,
  * and wide event sets and reductions are registered.
  *
  * A counter's value may trail its events by up to [[CountLatency]] cycles, a [[max]] by
  * [[maxLatency]]; the MAPM raises `done` only after it has been idle that long, and no event
  * happens while it is idle, so the counters read at `done` are exact.
  */
object Counters {
  /** Bits of a counter segment: the longest carry chain a counter has in one cycle. */
  val Segment = 16

  /** Event sets up to this size are counted in the cycle they happen; larger ones are
    * registered first (their population count is an adder tree of its own). */
  val DirectEvents = 4

  /** The most cycles a counter of [[count]] trails its events. */
  val CountLatency = 1

  /** An unsigned accumulator of `bits` bits (wrapping) that adds `inc` (narrower than a `segment`)
    * every cycle, exact every cycle: the low segment adds `inc`; each higher segment adds one
    * when every segment below it carries out, which it learns from the low segment's carry and
    * the registered all-ones flags of the segments in between (carry select, one segment's
    * chain deep). */
  def accumulate(inc: UInt, bits: Int, segment: Int = Segment): UInt = {
    require(bits >= 1 && inc.getWidth < segment, s"counter of $bits bits adding ${inc.getWidth}-bit values in $segment-bit segments")
    val widths = Seq.tabulate((bits + segment - 1) / segment)(k => math.min(segment, bits - k * segment))
    val segs = widths.map(w => RegInit(0.U(w.W)))
    val low = segs.head +& inc
    segs.head := low(widths.head - 1, 0)
    var carry = low(widths.head) // the carry into segment k this cycle
    for (k <- 1 until segs.size) {
      val s = segs(k)
      when(carry) { s := s + 1.U }
      carry = carry && s.andR
    }
    Cat(segs.reverse)
  }

  /** A counter of `bits` bits that adds, every cycle, how many of `events` are high (registered
    * first when there are more than [[DirectEvents]]). */
  def count(events: Seq[Bool], bits: Int = 64, segment: Int = Segment): UInt = {
    val n = if (events.size <= DirectEvents) PopCount(events) else {
      val r = RegInit(0.U(log2Ceil(events.size + 1).W))
      r := PopCount(events)
      r
    }
    accumulate(n, bits, segment)
  }

  /** The largest of `xs`, as a tree of two-input maxima with a register after every second
    * level and after the last: it trails its inputs by [[maxLatency]]`(xs.size)` cycles (meant for
    * quantities that only grow, like peaks). */
  def max(xs: Seq[UInt]): UInt = {
    require(xs.nonEmpty, "a max of nothing")
    var ys = xs
    var depth = 0
    while (ys.size > 1) {
      ys = ys.grouped(2).map {
        case Seq(a, b) => Mux(a > b, a, b)
        case Seq(a) => a
      }.toSeq
      depth += 1
      if (depth % 2 == 0 || ys.size == 1) ys = ys.map(y => RegNext(y, 0.U))
    }
    if (depth == 0) RegNext(ys.head, 0.U) else ys.head
  }

  /** The cycles [[max]] of `n` values trails them. */
  def maxLatency(n: Int): Int = math.max(1, (log2Ceil(n) + 1) / 2)
}
