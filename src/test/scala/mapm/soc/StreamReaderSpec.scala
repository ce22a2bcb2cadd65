package mapm.soc

import chisel3._
import chiseltest._
import mapm.memory.{DramModel, DramTiming, MemImage, MemSim}
import mapm.params.{CoprocParams, MapmParams}
import mapm.testutil.Sim
import org.scalatest.funsuite.AnyFunSuite
import scala.util.Random

/** [[StreamReader]] through a reordering DRAM with random stalls: the entries come out in stream
  * order, those naming a query beyond the count skipped and flagged, every count from 1 to a few
  * lines; without `useStream`, the indices 0 .. count - 1 in order and no read at all. */
class StreamReaderSpec extends AnyFunSuite with Sim {
  for (lines <- Seq(1, 3, 4)) test(s"$lines lines ahead: every entry in order, the bad ones skipped and flagged") {
    val p = MapmParams.small.copy(coproc = CoprocParams(streamLines = lines))
    simulate(new StreamReader(p)) { c =>
      c.clock.setTimeout(0)
      for ((count, seed) <- Seq(1, 15, 16, 17, 100, 333).zipWithIndex) {
        val rnd = new Random(seed * 10 + lines)
        val base = 256
        val withBad = seed % 2 == 1
        val stream = Array.tabulate(count)(_ => if (withBad && rnd.nextInt(10) == 0) count + rnd.nextInt(100) else rnd.nextInt(count))
        val bytes = Array.fill[Byte](base + (count * 4 + 63) / 64 * 64 + 64)(0)
        for ((q, k) <- stream.zipWithIndex; j <- 0 until 4) bytes(base + 4 * k + j) = ((q >> (8 * j)) & 0xff).toByte
        val mem = new MemImage(bytes)
        c.io.out.ready.poke(false.B); c.io.mem.resp.valid.poke(false.B); c.io.start.poke(false.B)
        MemSim.reset(c.clock, c.reset)
        c.io.streamBase.poke(base.U); c.io.queryCount.poke(count.U); c.io.useStream.poke(true.B)
        c.io.start.poke(true.B); c.clock.step(); c.io.start.poke(false.B)
        val dram = new DramModel(c.io.mem, mem, DramTiming(40, 0.7, 0.6), rnd)
        val got = scala.collection.mutable.ArrayBuffer[Int]()
        var taking = false
        MemSim.run(c.clock, Seq(() => dram.drive(), () => { taking = rnd.nextDouble() < 0.7; c.io.out.ready.poke(taking.B) }),
          Seq(() => dram.observe(), () => {
            val fire = taking && c.io.out.valid.peek().litToBoolean
            if (fire) got += c.io.out.bits.q.peek().litValue.toInt
            fire
          }), c.io.done.peek().litToBoolean && dram.outstanding == 0)
        assert(got.toSeq == stream.filter(_ < count).toSeq, s"count $count")
        assert(c.io.badQuery.peek().litToBoolean == stream.exists(_ >= count), s"count $count")
        assert(dram.requests.forall(a => a % 64 == 0 && a >= base && a < base + (count * 4 + 63) / 64 * 64), s"count $count: a read outside the stream")
      }
    }
  }

  test("without useStream: the indices 0 .. count - 1 in order under random back-pressure, and no read") {
    simulate(new StreamReader(MapmParams.small)) { c =>
      c.clock.setTimeout(0)
      for ((count, seed) <- Seq(1, 2, 17, 300).zipWithIndex) {
        val rnd = new Random(seed)
        c.io.out.ready.poke(false.B); c.io.mem.resp.valid.poke(false.B); c.io.mem.req.ready.poke(true.B); c.io.start.poke(false.B)
        MemSim.reset(c.clock, c.reset)
        c.io.streamBase.poke(0.U); c.io.queryCount.poke(count.U); c.io.useStream.poke(false.B)
        c.io.start.poke(true.B); c.clock.step(); c.io.start.poke(false.B); c.io.useStream.poke(true.B) // taken at start alone
        val got = scala.collection.mutable.ArrayBuffer[Int]()
        var cycles = 0
        while (!c.io.done.peek().litToBoolean && cycles < 10 * count + 100) {
          val take = rnd.nextDouble() < 0.6
          c.io.out.ready.poke(take.B)
          assert(!c.io.mem.req.valid.peek().litToBoolean, s"count $count: a read")
          if (take && c.io.out.valid.peek().litToBoolean) got += c.io.out.bits.q.peek().litValue.toInt
          c.clock.step(); cycles += 1
        }
        assert(got.toSeq == (0 until count), s"count $count")
        assert(!c.io.badQuery.peek().litToBoolean)
      }
    }
  }
}
