package mapm.soc

import chisel3._
import chisel3.util._
import chiseltest._
import mapm.axi.{Axi4Checker, Axi4Params}
import mapm.numerics.{FloatFormat, FrameAccum}
import mapm.params.{CoprocParams, MapmParams, ModuleCounts, NumberParams}
import mapm.testutil.Sim
import org.scalatest.funsuite.AnyFunSuite
import scala.collection.mutable
import scala.util.Random

/** The writer with a checker on its AXI4 write channels. */
class WriterChecked(p: MapmParams, ap: Axi4Params) extends Module {
  val writer = Module(new FrameWriter(p, ap))
  val checker = Module(new Axi4Checker(ap))
  val io = IO(new Bundle {
    val w = chiselTypeOf(writer.io)
    val masterFault = Output(UInt(Axi4Checker.MasterRules.size.W))
    val slaveFault = Output(UInt(Axi4Checker.SlaveRules.size.W))
  })
  io.w <> writer.io
  val a = checker.io.axi
  a.aw.valid := writer.io.aw.valid; a.aw.ready := writer.io.aw.ready; a.aw.bits := writer.io.aw.bits
  a.w.valid := writer.io.w.valid; a.w.ready := writer.io.w.ready; a.w.bits := writer.io.w.bits
  a.b.valid := writer.io.b.valid; a.b.ready := writer.io.b.ready; a.b.bits := writer.io.b.bits
  a.ar.valid := false.B; a.ar.ready := false.B; a.ar.bits := 0.U.asTypeOf(a.ar.bits)
  a.r.valid := false.B; a.r.ready := false.B; a.r.bits := 0.U.asTypeOf(a.r.bits)
  io.masterFault := checker.io.masterFault
  io.slaveFault := checker.io.slaveFault
}

/** [[FrameWriter]]: random accumulator entries of a pass at a random place in the frame buffer,
  * written through an AXI4 slave with random stalls; the buffer's bytes must be the model's
  * records ([[FrameAccum.resolve]], NaN for a refused pixel) exactly where the pass lies and
  * untouched around it, and the checker must flag nothing. fp32 (one pixel a beat), fp16 packed
  * (two a beat, strobes on partial beats) and fp64 (two beats a pixel). */
class FrameWriterSpec extends AnyFunSuite with Sim {
  private val ap = Axi4Params(addrBits = 32, dataBytes = 16, idBits = 4)

  for ((f, seed) <- Seq(FloatFormat.fp32 -> 1, FloatFormat.fp16 -> 2, FloatFormat.fp64 -> 3))
    test(s"$f: a pass of pixels written where it belongs, bursts inside 4 KiB pages, no rule broken") {
      val p2 = mapm.pipeline.Configure.of(1, 1, 1, f, 3).copy(coproc = CoprocParams(tileLog2 = 9))
      val fa = p2.frameAccum
      val pb = FrameWriter.pixelBytes(p2)
      simulate(new WriterChecked(p2, ap)) { c =>
        val rnd = new Random(seed)
        val memBytes = 1 << 16
        val mem = Array.fill[Byte](memBytes)(0x5a)
        val frameBase = 4096 - 64 // the pass crosses a 4 KiB boundary
        for (pass <- 0 until 2) {
          val pixelBase = rnd.nextInt(40)
          val count = 300 + rnd.nextInt(200)
          val scale = -30
          val entries = Array.fill(count) {
            val bad = rnd.nextInt(30) == 0
            (bad, Seq.fill(3)(BigInt(40, rnd) - (BigInt(1) << 38)))
          }
          val w = c.io.w
          w.frameBase.poke(frameBase.U); w.pixelBase.poke(pixelBase.U); w.pixelCount.poke(count.U); w.scale.poke(scale.S)
          w.readOut.valid.poke(false.B); w.aw.ready.poke(false.B); w.w.ready.poke(false.B); w.b.valid.poke(false.B)
          if (pass == 0) { c.reset.poke(true.B); c.clock.step(2); c.reset.poke(false.B) }
          w.start.poke(true.B); c.clock.step(); w.start.poke(false.B)
          var pendingRead: Option[Int] = None
          val bursts = mutable.Queue[(Long, Int)]() // address, beats left
          var cur: Option[(Long, Int)] = None
          var bOwed = 0
          var offeredB = false
          var cycles = 0
          while (!w.done.peek().litToBoolean) {
            // The accumulator: an entry the cycle after it is read.
            w.readOut.valid.poke(pendingRead.isDefined.B)
            pendingRead.foreach { i =>
              w.readOut.bits.bad.poke(entries(i)._1.B); w.readOut.bits.count.poke(1.U)
              for (ch <- 0 until 3) w.readOut.bits.sum(ch).poke(entries(i)._2(ch).S)
            }
            pendingRead = if (w.read.valid.peek().litToBoolean) Some(w.read.bits.peek().litValue.toInt) else None
            val awR = rnd.nextDouble() < 0.5; val wR = rnd.nextDouble() < 0.6
            w.aw.ready.poke(awR.B); w.w.ready.poke(wR.B)
            if (!offeredB && bOwed > 0 && rnd.nextDouble() < 0.5) offeredB = true
            w.b.valid.poke(offeredB.B); w.b.bits.id.poke(0.U); w.b.bits.resp.poke(0.U)
            if (awR && w.aw.valid.peek().litToBoolean)
              bursts.enqueue((w.aw.bits.addr.peek().litValue.toLong, w.aw.bits.len.peek().litValue.toInt + 1))
            if (wR && w.w.valid.peek().litToBoolean) {
              if (cur.isEmpty) cur = Some(bursts.dequeue())
              val (addr, left) = cur.get
              val data = w.w.bits.data.peek().litValue
              val strb = w.w.bits.strb.peek().litValue
              for (j <- 0 until 16 if strb.testBit(j)) mem((addr + j).toInt) = ((data >> (8 * j)) & 0xff).toByte
              assert(w.w.bits.last.peek().litToBoolean == (left == 1))
              cur = if (left == 1) { bOwed += 1; None } else Some((addr + 16, left - 1))
            }
            if (offeredB && w.b.ready.peek().litToBoolean) { offeredB = false; bOwed -= 1 }
            c.clock.step(); cycles += 1
            assert(cycles < 50000, "the writer did not finish")
          }
          assert(!w.error.peek().litToBoolean && c.io.masterFault.peek().litValue == 0 && c.io.slaveFault.peek().litValue == 0)
          val first = frameBase + pixelBase * pb
          for (a <- 0 until memBytes) {
            val k = (a - first) / pb
            if (a >= first && k < count) {
              val (bad, sums) = entries(k)
              val slot = pb / 4
              val ch = (a - first) % pb / slot
              val byte = (a - first) % slot
              val v = if (ch == 3) 0L else if (bad) f.quietNaN else fa.resolve(sums(ch), scale)
              assert((mem(a) & 0xff) == ((v >>> (8 * byte)) & 0xff), s"pass $pass pixel $k channel $ch byte $byte")
            } else if (pass == 0) assert(mem(a) == 0x5a.toByte, s"byte $a outside the pass written")
          }
        }
      }
    }
}
