package mapm.tsearch

import mapm.Slow
import chisel3._
import chiseltest._
import mapm.testutil.Sim
import org.scalatest.funsuite.AnyFunSuite
import scala.util.Random

/** [[RegisterStack]] against a Scala stack: random pushes (none, one on either port, or both) and
  * pops every cycle, the top, count and peak compared each cycle, and the overflow flag when
  * pushes go beyond the depth. */
@Slow
class RegisterStackSpec extends AnyFunSuite with Sim {
  private val width = 12

  /** Drives `cycles` random cycles; `pushBias` is the probability of each push port being valid
    * (pushes beyond the depth are allowed only when `allowOverflow`). */
  private def run(depth: Int, cycles: Int, seed: Long, pushBias: Double, allowOverflow: Boolean): (Int, Boolean) = {
    var peakSeen = 0
    var overflowed = false
    simulate(new RegisterStack(UInt(width.W), depth)) { c =>
      val rnd = new Random(seed)
      val ref = scala.collection.mutable.ArrayBuffer[Int]()
      var peak = 0
      for (cycle <- 0 until cycles) {
        assert(c.io.count.peek().litValue == ref.size, s"cycle $cycle: count")
        assert(c.io.top.valid.peek().litToBoolean == ref.nonEmpty, s"cycle $cycle: top.valid")
        if (ref.nonEmpty) assert(c.io.top.bits.peek().litValue == ref.last, s"cycle $cycle: top")
        assert(c.io.peak.peek().litValue == peak, s"cycle $cycle: peak")
        assert(c.io.overflow.peek().litToBoolean == overflowed, s"cycle $cycle: overflow")
        val pop = ref.nonEmpty && rnd.nextDouble() < 0.5
        val after = ref.size - (if (pop) 1 else 0)
        val want = Seq.fill(2)(rnd.nextDouble() < pushBias)
        val room = if (allowOverflow) 2 else depth - after
        // Keep within the room unless overflow is the point; either port may carry a lone push.
        val valid = if (want.count(identity) <= room) want else if (room == 1) Seq(false, true) else Seq(false, false)
        val values = Seq.fill(2)(rnd.nextInt(1 << width))
        c.io.pop.poke(pop.B)
        for (k <- 0 until 2) {
          c.io.push(k).valid.poke(valid(k).B)
          c.io.push(k).bits.poke(values(k).U)
        }
        c.clock.step()
        if (pop) ref.remove(ref.size - 1)
        for (k <- 0 until 2 if valid(k)) { if (ref.size < depth) ref += values(k) else overflowed = true }
        peak = peak max ref.size
      }
      peakSeen = peak
    }
    (peakSeen, overflowed)
  }

  test("depths 8, 7 and 26: 20,000 random cycles of pushes and pops against a Scala stack") {
    for ((depth, seed) <- Seq(8 -> 1L, 8 -> 2L, 7 -> 3L, 26 -> 4L)) {
      val (peak, overflowed) = run(depth, 20000, seed, 0.3, allowOverflow = false)
      assert(peak == depth && !overflowed, s"depth $depth seed $seed: the stack filled up (peak $peak) without overflow")
    }
  }

  test("depth 256 (the default bank): 20,000 random cycles drifting toward full") {
    val (peak, overflowed) = run(256, 20000, 7, 0.26, allowOverflow = false)
    assert(peak > 100 && !overflowed, s"peak $peak")
  }

  test("pushes beyond the depth raise the sticky overflow and are not written") {
    val (peak, overflowed) = run(4, 2000, 11, 0.6, allowOverflow = true)
    assert(overflowed && peak == 4)
  }
}
