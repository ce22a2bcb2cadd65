package mapm.soc

import chisel3._
import chiseltest._
import mapm.testutil.Sim
import org.scalatest.funsuite.AnyFunSuite
import scala.collection.mutable
import scala.util.Random

/** [[FrameCombiner]] under random input timing and random output stalls: every partial reaches the
  * output its destination names, and per pixel the sums, good counts and refusal flags that come
  * out are those that went in (nothing lost, nothing counted twice), whatever merged on the way;
  * hot pixels (many inputs at once) come out merged; power-of-two and other port counts. */
class FrameCombinerSpec extends AnyFunSuite with Sim {
  private val tileLog2 = 6

  private def run(inputs: Int, outputs: Int, seed: Int, pixels: Int, items: Int, stall: Double): Int = {
    val parts = FrameAccumulator.maxParts(inputs, outputs)
    val sumBits = 20
    var outCount = 0
    simulate(new FrameCombiner(inputs, outputs, tileLog2, sumBits, parts)) { c =>
      val rnd = new Random(seed)
      // What went in and what came out, per pixel: (sum per channel, good, nonFinite, range).
      val sent = mutable.Map[Int, (Seq[BigInt], Int, Boolean, Boolean)]().withDefaultValue((Seq.fill(3)(BigInt(0)), 0, false, false))
      val got = mutable.Map[Int, (Seq[BigInt], Int, Boolean, Boolean)]().withDefaultValue((Seq.fill(3)(BigInt(0)), 0, false, false))
      def plus(m: mutable.Map[Int, (Seq[BigInt], Int, Boolean, Boolean)], px: Int, s: Seq[BigInt], g: Int, nf: Boolean, rg: Boolean) = {
        val (s0, g0, nf0, rg0) = m(px)
        m(px) = (s0.zip(s).map { case (a, b) => a + b }, g0 + g, nf0 || nf, rg0 || rg)
      }
      val pending = Array.fill(inputs)(Option.empty[(Int, Seq[BigInt], Boolean, Boolean)])
      var left = items
      var cycle = 0
      def dest(px: Int) = px % outputs
      while (left > 0 || pending.exists(_.isDefined) || !c.io.idle.peek().litToBoolean) {
        for (i <- 0 until inputs) {
          if (pending(i).isEmpty && left > 0 && rnd.nextDouble() < 0.7) {
            val px = rnd.nextInt(pixels)
            val bad = rnd.nextInt(30)
            pending(i) = Some((px, Seq.fill(3)(BigInt(rnd.nextInt(2001) - 1000)), bad == 0, bad == 1))
            left -= 1
          }
          val in = c.io.in(i)
          in.valid.poke(pending(i).isDefined.B)
          pending(i).foreach { case (px, s, nf, rg) =>
            in.bits.offset.poke(px.U)
            val good = !nf && !rg
            for (ch <- 0 until 3) in.bits.sum(ch).poke((if (good) s(ch) else BigInt(0)).S)
            in.bits.good.poke((if (good) 1 else 0).U)
            in.bits.nonFinite.poke(nf.B); in.bits.range.poke(rg.B)
            c.io.dest(i).poke(dest(px).U)
          }
        }
        val ready = Seq.fill(outputs)(rnd.nextDouble() >= stall)
        for (o <- 0 until outputs) c.io.out(o).ready.poke(ready(o).B)
        for (o <- 0 until outputs if ready(o) && c.io.out(o).valid.peek().litToBoolean) {
          val b = c.io.out(o).bits
          val px = b.offset.peek().litValue.toInt
          assert(dest(px) == o, s"pixel $px came out on $o")
          plus(got, px, (0 until 3).map(ch => b.sum(ch).peek().litValue), b.good.peek().litValue.toInt,
            b.nonFinite.peek().litToBoolean, b.range.peek().litToBoolean)
          outCount += 1
        }
        for (i <- 0 until inputs if pending(i).isDefined && c.io.in(i).ready.peek().litToBoolean) {
          val (px, s, nf, rg) = pending(i).get
          val good = !nf && !rg
          plus(sent, px, if (good) s else Seq.fill(3)(BigInt(0)), if (good) 1 else 0, nf, rg)
          pending(i) = None
        }
        c.clock.step(); cycle += 1
        assert(cycle < 100000, "no progress")
      }
      assert(got == sent)
    }
    outCount
  }

  test("8 x 8 ports, 64 pixels, outputs stalling a quarter of the time: every partial at its bank, every sum kept") {
    run(8, 8, 1, 64, 3000, 0.25)
  }

  test("6 inputs to 4 outputs and 3 to 5 (padded to a power of two), with stalls") {
    run(6, 4, 2, 40, 2000, 0.3)
    run(3, 5, 3, 40, 1500, 0.3)
  }

  test("one hot pixel from 16 inputs: partials merge on the way (far fewer out than in)") {
    val out = run(16, 16, 4, 1, 4000, 0.5)
    assert(out < 4000 / 2, s"$out partials out of 4000 contributions")
  }
}
