package mapm.memory

import chisel3._
import chiseltest._
import org.scalatest.funsuite.AnyFunSuite
import scala.collection.mutable
import scala.util.Random

/** [[RegFifo]] against a Scala queue, cycle by cycle under random offers and random stalls: every
  * entry leaves once, in order; `enq.ready` is low exactly when the queue holds `entries`; `count`
  * is the occupancy; with `flow`, an entry reaches `deq` in the cycle it arrives at an empty queue,
  * and without it never does. */
class RegFifoSpec extends AnyFunSuite with ChiselScalatestTester {
  private def check(entries: Int, flow: Boolean, seed: Int, cycles: Int = 600): Unit =
    test(new RegFifo(UInt(8.W), entries, flow)) { c =>
      val rnd = new Random(seed)
      val model = mutable.Queue.empty[Int]
      var next = 0
      var passedThrough = 0
      for (cycle <- 0 until cycles) {
        val offer = rnd.nextDouble() < 0.6
        val take = rnd.nextDouble() < 0.55
        c.io.enq.valid.poke(offer.B)
        c.io.enq.bits.poke((next & 0xff).U)
        c.io.deq.ready.poke(take.B)
        assert(c.io.count.peekInt() == model.size, s"cycle $cycle: count")
        val ready = model.size < entries
        c.io.enq.ready.expect(ready.B, s"cycle $cycle: enq.ready")
        val head = if (model.nonEmpty) Some(model.head) else if (flow && offer) Some(next & 0xff) else None
        c.io.deq.valid.expect(head.isDefined.B, s"cycle $cycle: deq.valid")
        head.foreach(h => c.io.deq.bits.expect(h.U, s"cycle $cycle: deq.bits"))
        val wasEmpty = model.isEmpty
        if (offer && ready) { model.enqueue(next & 0xff); next += 1 }
        if (take && head.isDefined) {
          if (wasEmpty) passedThrough += 1
          model.dequeue()
        }
        c.clock.step()
      }
      assert(next > cycles / 5, "entries flowed") // a one-entry queue without flow takes one every other cycle
      if (flow) assert(passedThrough > 0, "some entries passed straight through an empty queue")
    }

  for (entries <- 1 to 4; flow <- Seq(false, true); seed <- 1 to 2) {
    test(s"$entries entries${if (flow) ", flow-through" else ""}, seed $seed: in order, once each, ready and count as the model's") {
      check(entries, flow, seed)
    }
  }
}
