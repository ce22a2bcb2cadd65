package mapm.util

import chisel3._
import chiseltest._
import mapm.testutil.Sim
import org.scalatest.funsuite.AnyFunSuite
import scala.util.Random

/** The performance counters' building blocks against plain arithmetic, cycle by cycle, at small
  * segment widths so that every segment's carry and the wrap are exercised. */
class CountersSpec extends AnyFunSuite with Sim {
  private class Acc(bits: Int, segment: Int, incBits: Int) extends Module {
    val inc = IO(Input(UInt(incBits.W)))
    val out = IO(Output(UInt(bits.W)))
    out := Counters.accumulate(inc, bits, segment)
  }
  private class Count(n: Int, bits: Int, segment: Int) extends Module {
    val events = IO(Input(Vec(n, Bool())))
    val out = IO(Output(UInt(bits.W)))
    out := Counters.count(events, bits, segment)
  }
  private class Max(n: Int, w: Int) extends Module {
    val in = IO(Input(Vec(n, UInt(w.W))))
    val out = IO(Output(UInt(w.W)))
    out := Counters.max(in)
  }

  for ((bits, segment, incBits) <- Seq((7, 2, 1), (9, 3, 2), (10, 4, 3), (20, 16, 5))) {
    test(s"accumulate: $bits bits in $segment-bit segments adding $incBits-bit values is exact every cycle, wrap included") {
      simulate(new Acc(bits, segment, incBits)) { c =>
        val rnd = new Random(bits)
        var ref = BigInt(0)
        for (_ <- 0 until 3000) {
          assert(c.out.peek().litValue == ref)
          val i = rnd.nextInt(1 << incBits)
          c.inc.poke(i.U)
          c.clock.step()
          ref = (ref + i) % (BigInt(1) << bits)
        }
      }
    }
  }

  for (n <- Seq(1, 4, 5, 13)) {
    test(s"count of $n events: exact every cycle up to ${Counters.DirectEvents} events, one cycle behind above") {
      val lag = if (n > Counters.DirectEvents) 1 else 0
      simulate(new Count(n, 12, 5)) { c =>
        val rnd = new Random(n)
        val refs = scala.collection.mutable.ArrayBuffer(BigInt(0))
        for (t <- 0 until 1500) {
          val want = refs(math.max(0, refs.size - 1 - lag))
          assert(c.out.peek().litValue == want, s"cycle $t")
          val ev = Seq.fill(n)(rnd.nextBoolean())
          c.events.zip(ev).foreach { case (p, v) => p.poke(v.B) }
          c.clock.step()
          refs += (refs.last + ev.count(identity)) % 4096
        }
      }
    }
  }

  for (n <- Seq(1, 2, 3, 5, 16, 17)) {
    test(s"max of $n values: the maximum exactly ${Counters.maxLatency(n)} cycles later") {
      val lag = Counters.maxLatency(n)
      simulate(new Max(n, 5)) { c =>
        val rnd = new Random(n)
        val hist = scala.collection.mutable.ArrayBuffer.empty[Int]
        for (t <- 0 until 400) {
          if (hist.size >= lag) assert(c.out.peek().litValue == hist(hist.size - lag), s"cycle $t")
          val xs = Seq.fill(n)(rnd.nextInt(32))
          c.in.zip(xs).foreach { case (p, v) => p.poke(v.U) }
          c.clock.step()
          hist += xs.max
        }
      }
    }
  }
}
