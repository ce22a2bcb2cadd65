package mapm.soc

import chisel3._
import chisel3.util._
import mapm.numerics.FrameAccum
import mapm.params.{MapmParams, Rgb, SoResult}
import mapm.shader.SomLane
import mapm.util.{Index, RoundRobin}

/** A pixel's entry in the frame accumulator ([[FrameAccum]]): a fixed-point sum per channel, the
  * contributions counted, and whether one was refused (the pixel then reads NaN). */
class PixelSums(fa: FrameAccum) extends Bundle {
  val bad = Bool()
  val count = UInt(fa.countBits.W)
  val sum = Vec(Rgb.Channels, SInt(fa.accBits.W))
}

/** A passing SO's colour on its way to its pixel's bank, converted to the accumulator's fixed point
  * ([[FrameConvert]]): the pixel's offset in the tile, the values, and whether a channel was
  * refused. */
class Contribution(p: MapmParams) extends Bundle {
  val offset = UInt(p.coproc.tileLog2.W)
  val value = Vec(Rgb.Channels, SInt((p.frameAccum.limitBits + 1).W))
  val nonFinite = Bool()
  val range = Bool()
}

/** The frame accumulator (docs/coprocessor.md, "Accumulation"): adds the colour of every SO whose
  * cond holds into its pixel as [[FrameAccum]] defines it, so the sums are the same whatever order
  * the SOs come in, and hands the pixels to the frame writer at the end of the pass.
  *
  * Each result port feeds a FIFO of [[SomLane.resultFifo]] entries (an SRAM); `room` tells the port's
  * SOM lane how many entries are free, and the lane takes new SOs only while everything it has
  * fits, so no result is ever dropped (`overflow` would say so). The pixels of the tile (up to
  * 2^tileLog2) are spread over `frameBanks` banks by the low bits of their offset from
  * `pixelBase`. The FIFO heads reach their banks through a combining network ([[FrameCombiner]]),
  * which adds contributions of the same pixel into one partial wherever they meet (one query's
  * passing SOs, spread over the lanes, all go to its pixel within a few cycles); each bank takes one
  * partial a cycle, reads the pixel's entry and writes the sum back the next cycle, forwarding it
  * to a read of the same pixel in between. The sums are integers, so adding several in one step is
  * the same as adding them one by one. Each port converts its results ([[FrameConvert]]) before
  * its FIFO. A result whose pixel lies outside `pixelBase .. pixelBase + pixelCount - 1` is refused
  * (fault `pixel`).
  *
  * `clear` zeroes the pass's pixels (one row of every bank a cycle: pixelCount / banks cycles;
  * `ready` is low meanwhile and the FIFOs hold the pass's first results). `read` reads a pixel's entry for the writer (`readOut` the next cycle); it is for
  * when the accumulator is `idle`.
  *
  * Latency: log2(ports) + 3 cycles from a result to its pixel's entry when nothing waits.
  * Throughput: one partial a cycle per bank.
  */
class FrameAccumulator(p: MapmParams) extends Module {
  private val fa = p.frameAccum
  private val lanes = p.counts.som * p.counts.soaPerSom
  private val banks = p.frameBanks
  private val tileLog2 = p.coproc.tileLog2
  private val bankBits = log2Ceil(banks)
  private val rows = (1 << tileLog2) / banks
  private val depth = SomLane.resultFifo(p)
  override def desiredName = s"FrameAccumulator_l${lanes}_b${banks}_t$tileLog2"

  val io = IO(new Bundle {
    val results = Input(Vec(lanes, Valid(new SoResult(p))))
    val room = Output(Vec(lanes, UInt(log2Ceil(depth + 1).W)))
    val scale = Input(SInt(FrameArith.ScaleBits.W))
    val pixelBase = Input(UInt(32.W))
    val pixelCount = Input(UInt((tileLog2 + 1).W))
    val clear = Input(Bool())
    val ready = Output(Bool())
    val idle = Output(Bool())
    /** Sticky since `clear`: a colour not finite, beyond the scale's range, a count full, a pixel outside the pass. */
    val faults = Output(new FrameFaults)
    val overflow = Output(Bool())
    val read = Flipped(Valid(UInt(tileLog2.W)))
    val readOut = Valid(new PixelSums(fa))
  })

  // Clearing: one row of every bank per cycle, the rows the pass's pixels use.
  private val clearing = RegInit(false.B)
  private val clearRow = RegInit(0.U(log2Ceil(rows + 1).W))
  private val usedRows = (io.pixelCount +& (banks - 1).U) >> bankBits
  when(io.clear) { clearing := true.B; clearRow := 0.U }
  .elsewhen(clearing) { clearRow := clearRow + 1.U; when(clearRow + 1.U >= usedRows) { clearing := false.B } }
  io.ready := !clearing

  private val faults = RegInit(0.U.asTypeOf(new FrameFaults))
  private val overflow = RegInit(false.B)
  when(io.clear) { faults := 0.U.asTypeOf(new FrameFaults); overflow := false.B }

  // One FIFO per result port: the passing results whose pixel is in the pass.
  private val fifos = Seq.fill(lanes)(Module(new Queue(new Contribution(p), depth, useSyncReadMem = true)))
  private val pixelOut = WireInit(false.B)
  for ((f, l) <- fifos.zipWithIndex) {
    val r = io.results(l)
    val offset = r.bits.pixel -& io.pixelBase
    val inPass = r.bits.pixel >= io.pixelBase && offset < io.pixelCount
    f.io.enq.valid := r.valid && r.bits.cond && inPass
    f.io.enq.bits.offset := offset(tileLog2 - 1, 0)
    val conv = Seq.fill(Rgb.Channels)(Module(new FrameConvert(fa)))
    for ((cv, ch) <- conv.zipWithIndex) { cv.io.in := r.bits.colour(ch); cv.io.scale := io.scale; f.io.enq.bits.value(ch) := cv.io.out }
    f.io.enq.bits.nonFinite := conv.map(_.io.nonFinite).reduce(_ || _)
    f.io.enq.bits.range := conv.map(_.io.range).reduce(_ || _)
    when(r.valid && r.bits.cond && !inPass) { pixelOut := true.B }
    when(f.io.enq.valid && !f.io.enq.ready) { overflow := true.B }
    // The FIFO's free entries, also while clearing (its results wait for the clear): a lane's room
    // falls only by the results it sends, as the ring Data bus's credits need (RingBus).
    io.room(l) := depth.U - f.io.count
  }
  when(pixelOut) { faults.pixel := true.B }

  private def bankOf(c: Contribution): UInt = if (banks == 1) 0.U else c.offset(bankBits - 1, 0)
  private def rowOf(offset: UInt): UInt = if (banks == (1 << tileLog2)) 0.U else offset >> bankBits

  private val bankIdle = Wire(Vec(banks, Bool()))
  private val readBank = RegNext(if (banks == 1) 0.U else io.read.bits(bankBits - 1, 0))
  private val readValid = RegNext(io.read.valid, false.B)
  private val readData = Wire(Vec(banks, new PixelSums(fa)))

  // The FIFO heads through the combining network to their banks, the same pixel's added on the way.
  private val parts = FrameAccumulator.maxParts(lanes, banks)
  private val sumBits = FramePartial.sumBits(fa, parts)
  val net = Module(new FrameCombiner(lanes, banks, tileLog2, sumBits, parts))
  for ((f, l) <- fifos.zipWithIndex) {
    val c = f.io.deq.bits
    val good = !c.nonFinite && !c.range
    val in = net.io.in(l)
    in.valid := f.io.deq.valid
    in.bits.offset := c.offset
    for (ch <- 0 until Rgb.Channels) in.bits.sum(ch) := Mux(good, c.value(ch), 0.S)
    in.bits.good := good.asUInt
    in.bits.nonFinite := c.nonFinite
    in.bits.range := c.range
    net.io.dest(l) := bankOf(c)
    f.io.deq.ready := in.ready
  }

  for (b <- 0 until banks) {
    val mem = SyncReadMem(rows, new PixelSums(fa))
    // Stage 1: the bank's partial taken; its row read.
    val o = net.io.out(b)
    o.ready := !clearing
    val any = o.fire
    val v1 = RegNext(any, false.B)
    val row1 = RegEnable(rowOf(o.bits.offset), any)
    val add1 = RegEnable(o.bits.sum, any)
    val good1 = RegEnable(o.bits.good, any)
    val nonFinite1 = RegEnable(o.bits.nonFinite, any)
    val range1 = RegEnable(o.bits.range, any)
    val readRow = Mux(io.read.valid, rowOf(io.read.bits), row1)
    val rdata = mem.read(readRow, true.B)
    readData(b) := rdata
    // Stage 2: add and write back; the sum just written is forwarded to a read of the same row.
    val v2 = RegNext(v1, false.B)
    val row2 = RegNext(row1)
    val add2 = RegNext(add1)
    val good2 = RegNext(good1)
    val nonFinite2 = RegNext(nonFinite1)
    val range2 = RegNext(range1)
    val last = RegInit(0.U.asTypeOf(Valid(new Bundle { val row = UInt(log2Ceil(rows).max(1).W); val data = new PixelSums(fa) })))
    val old = Mux(last.valid && last.bits.row === row2, last.bits.data, rdata)
    // The good contributions count (the model counts each good one, and refuses those beyond the count's range).
    val counted = old.count +& good2
    val full = counted > fa.maxCount.U
    val refused = nonFinite2 || range2 || full
    val upd = Wire(new PixelSums(fa))
    upd.bad := old.bad || refused
    upd.count := Mux(full, fa.maxCount.U, counted)
    for (ch <- 0 until Rgb.Channels) upd.sum(ch) := Mux(refused, old.sum(ch), old.sum(ch) + add2(ch))
    when(clearing) { mem.write(clearRow, 0.U.asTypeOf(new PixelSums(fa))) }
    .elsewhen(v2) { mem.write(row2, upd) }
    last.valid := v2 && !clearing
    last.bits.row := row2
    last.bits.data := upd
    when(v2 && nonFinite2) { faults.nonFinite := true.B }
    when(v2 && range2) { faults.range := true.B }
    when(v2 && full) { faults.count := true.B }
    bankIdle(b) := !v1 && !v2
  }
  io.faults := faults
  io.overflow := overflow
  io.idle := fifos.map(f => !f.io.deq.valid).reduce(_ && _) && net.io.idle && bankIdle.asUInt.andR && !clearing
  io.readOut.valid := readValid
  io.readOut.bits := readData(readBank)
}

/** The accumulation's faults, one bit each (the ERROR_CAUSE bits of the same names). */
object FrameAccumulator {
  /** The most good contributions one partial may carry (the network stops merging there): four
    * per network port. */
  def maxParts(lanes: Int, banks: Int): Int = 4 << log2Ceil(lanes max banks max 2)
}

class FrameFaults extends Bundle {
  val pixel = Bool()
  val count = Bool()
  val range = Bool()
  val nonFinite = Bool()
}
