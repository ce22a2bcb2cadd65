package mapm.testutil

/** A pipe's input stream for latency and loss checks: the first `backToBack` operations on
  * consecutive cycles, then each later one after a run of bubbles (a bubble before it with
  * probability `bubble`, repeated). [[inCycle]] records the cycle each operation entered, filled
  * as the stream is consumed. */
final class Bubbles[T](ops: IndexedSeq[T], backToBack: Int, bubble: Double, seed: Long) {
  require(bubble >= 0 && bubble < 1, s"bubble probability must be in [0, 1), got $bubble")
  /** inCycle(k): the cycle operation k entered (valid once the stream has passed it). */
  val inCycle: Array[Long] = new Array[Long](ops.length)

  /** One element per cycle: `Some(op)` or a bubble. */
  val stream: Iterator[Option[T]] = {
    val rnd = new scala.util.Random(seed)
    var cycle = -1L
    ops.iterator.zipWithIndex.flatMap { case (op, k) =>
      val bubbles = if (k < backToBack) 0 else Iterator.continually(rnd.nextDouble() < bubble).takeWhile(identity).length
      Iterator.fill(bubbles)(None) ++ Iterator.single(Some((op, k)))
    }.map { c =>
      cycle += 1
      c.map { case (op, k) => inCycle(k) = cycle; op }
    }
  }
}
