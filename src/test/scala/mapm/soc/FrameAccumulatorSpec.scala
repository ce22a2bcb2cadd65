package mapm.soc

import chisel3._
import chiseltest._
import mapm.numerics.{FloatFormat, FrameSums}
import mapm.params.{CoprocParams, MapmParams, ModuleCounts}
import mapm.shader.SomLane
import mapm.testutil.Sim
import org.scalatest.funsuite.AnyFunSuite
import scala.collection.mutable
import scala.util.Random

/** [[FrameAccumulator]] against the model's frame ([[FrameSums]]): result ports that keep within the
  * room the accumulator gives (each a pipeline of fixed latency, as a SOM lane is), random pixels
  * (some outside the pass), random colours and conds; every pixel's sums, count and refusal read
  * back equal to the model's, the faults the model's, nothing dropped. */
class FrameAccumulatorSpec extends AnyFunSuite with Sim {
  private val f = FloatFormat.fp32

  private def params(fifo: Int, banks: Int) = MapmParams.small.copy(counts = ModuleCounts(1, 2, 2),
    coproc = CoprocParams(tileLog2 = 5, laneFifo = fifo, banks = banks))

  private def run(p: MapmParams, seed: Int, results: Int, colour: Random => Long, scale: Int, count: Int = 29): Unit =
    simulate(new FrameAccumulator(p)) { c =>
      val rnd = new Random(seed)
      val lanes = 4
      val latency = 7
      val base = 100
      c.io.scale.poke(scale.S); c.io.pixelBase.poke(base.U); c.io.pixelCount.poke(count.U)
      c.io.read.valid.poke(false.B)
      c.io.results.foreach(_.valid.poke(false.B))
      c.io.clear.poke(true.B); c.clock.step(); c.io.clear.poke(false.B)
      while (!c.io.ready.peek().litToBoolean) c.clock.step()
      val model = new FrameSums(p.frameAccum, count, 3, scale)
      var pixelFault = false
      // Each lane: a pipeline of `latency` stages; an op enters only while all it has fits the room.
      val pipes = Array.fill(lanes)(mutable.Queue[(Int, Option[(Int, Seq[Long], Boolean)])]())
      var issued = 0
      var cycle = 0
      while (issued < results || pipes.exists(_.nonEmpty)) {
        for (l <- 0 until lanes) {
          val room = c.io.room(l).peek().litValue.toInt
          val out = pipes(l).headOption.filter(_._1 <= cycle).map(_ => pipes(l).dequeue()._2).flatten
          c.io.results(l).valid.poke(out.isDefined.B)
          out.foreach { case (px, col, cond) =>
            val r = c.io.results(l).bits
            r.pixel.poke(px.U); r.cond.poke(cond.B)
            for (ch <- 0 until 3) r.colour(ch).poke(col(ch).U)
            if (cond) { if (px >= base && px < base + count) model.add(px - base, col) else pixelFault = true }
          }
          if (issued < results && rnd.nextDouble() < 0.8 && pipes(l).size + 1 <= room) {
            val px = if (rnd.nextInt(50) == 0) base + count + rnd.nextInt(5) else base + rnd.nextInt(count)
            pipes(l).enqueue((cycle + latency, Some((px, Seq.fill(3)(colour(rnd)), rnd.nextInt(5) < 2))))
            issued += 1
          }
        }
        c.clock.step(); cycle += 1
        assert(cycle < 200000, "no progress")
      }
      c.io.results.foreach(_.valid.poke(false.B))
      while (!c.io.idle.peek().litToBoolean) c.clock.step()
      assert(!c.io.overflow.peek().litToBoolean, "a result was dropped")
      val ft = c.io.faults
      assert(ft.pixel.peek().litToBoolean == pixelFault)
      assert(ft.nonFinite.peek().litToBoolean == ((model.faults & 1) != 0) && ft.range.peek().litToBoolean == ((model.faults & 2) != 0))
      for (i <- 0 until count) {
        c.io.read.valid.poke(true.B); c.io.read.bits.poke(i.U)
        c.clock.step()
        c.io.read.valid.poke(false.B)
        val o = c.io.readOut.bits
        assert(c.io.readOut.valid.peek().litToBoolean)
        val bad = model.resolve(i).exists(f.isNaN)
        assert(o.bad.peek().litToBoolean == bad, s"pixel $i")
        if (!bad) {
          assert(o.count.peek().litValue == model.count(i), s"pixel $i count")
          for (ch <- 0 until 3) assert(o.sum(ch).peek().litValue == model.sum(i, ch), s"pixel $i channel $ch")
        }
      }
    }

  private def ordinary(r: Random): Long = f.pack(r.nextInt(2), f.bias - 10 + r.nextInt(12), r.nextLong() & f.manMask)

  test("room of 6 a lane (the lanes wait often), 2 banks: 3,000 results, sums and counts equal to the model's") {
    run(params(6, 2), 1, 3000, ordinary, -30)
  }

  test("room by the SOA's latency, one bank (every lane into it), and a bank per pixel") {
    val p = params(0, 1)
    assert(SomLane.resultFifo(p) > 40)
    run(p, 2, 2000, ordinary, -30)
    run(params(8, 32), 3, 2000, ordinary, -30)
  }

  test("two hot pixels: every lane's results for the same pixel, added four at a time, still the model's sums") {
    run(params(6, 2), 5, 3000, ordinary, -30, count = 2)
    run(params(0, 4), 6, 3000, ordinary, -30, count = 1)
  }

  test("NaN, infinities and colours beyond the scale: those pixels refused, the rest kept, the faults raised") {
    def wild(r: Random): Long = r.nextInt(40) match {
      case 0 => f.quietNaN
      case 1 => f.posInf
      case 2 => f.encode(3.0e5) // beyond 2^39 units at scale -20
      case _ => ordinary(r)
    }
    run(params(6, 4), 4, 1500, wild, -20)
  }
}
