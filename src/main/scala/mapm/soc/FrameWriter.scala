package mapm.soc

import chisel3._
import chisel3.util._
import mapm.axi.{Axi4, Axi4Addr, Axi4B, Axi4Params, Axi4W}
import mapm.params.{MapmParams, Rgb}

/** Writes a frame pass's pixels into the frame buffer (docs/coprocessor.md, "Frame buffer"): pixel
  * k of the pass, the accumulator's entry k rounded once to the format ([[FrameResolve]]; a refused
  * pixel is the format's quiet NaN in every channel), becomes the record (r, g, b, 0) in four value
  * slots at `frameBase + (pixelBase + k) * pixelBytes`.
  *
  * It reads one entry a cycle from the accumulator (while the output has room), lays the records
  * into beats of the AXI4 data width (strobes cover only the pass's bytes), and writes them in
  * INCR bursts of up to 16 beats that never cross 4 KiB, AW before its W beats, under id 0, at most
  * [[FrameWriter.MaxWrites]] awaiting their B. `done`
  * rises when every burst's B has come back; `error` is sticky if one came back SLVERR or DECERR.
  *
  * Latency: about 3 cycles from an entry to its beat. Throughput: one pixel a cycle while a beat
  * holds one or more pixels; one beat a cycle with 8-byte slots (two beats a pixel).
  */
class FrameWriter(p: MapmParams, ap: Axi4Params) extends Module {
  private val fa = p.frameAccum
  private val fmt = p.numbers.format
  private val slot = p.slotBytes
  private val tileLog2 = p.coproc.tileLog2
  private val db = ap.dataBytes
  private val pb = FrameWriter.pixelBytes(p)
  private val chunk = math.min(pb, db)
  private val perBeat = db / chunk
  private val perPixel = pb / chunk
  require(db % chunk == 0 && pb % chunk == 0, s"a $pb-byte pixel record and $db-byte beats")
  override def desiredName = s"FrameWriter_${fmt.name}_s${slot}_d$db"

  val io = IO(new Bundle {
    val start = Input(Bool())
    val frameBase = Input(UInt(ap.addrBits.W))
    val pixelBase = Input(UInt(32.W))
    val pixelCount = Input(UInt((tileLog2 + 1).W))
    val scale = Input(SInt(FrameArith.ScaleBits.W))
    val read = Valid(UInt(tileLog2.W))
    val readOut = Flipped(Valid(new PixelSums(fa)))
    val aw = Decoupled(new Axi4Addr(ap))
    val w = Decoupled(new Axi4W(ap))
    val b = Flipped(Decoupled(new Axi4B(ap)))
    val busy = Output(Bool())
    val done = Output(Bool())
    val error = Output(Bool())
  })

  private val busy = RegInit(false.B)
  private val done = RegInit(false.B)
  private val error = RegInit(false.B)
  private val first = io.frameBase + io.pixelBase * pb.U
  private val end = first + io.pixelCount * pb.U
  private def down(a: UInt) = a & (~(db - 1).U(ap.addrBits.W)).asUInt
  private val beatsTotal = (down(end + (db - 1).U) - down(first)) >> log2Ceil(db)

  // Reading entries: one a cycle while the pixel queue has room for it and the one in flight.
  private val pixels = Module(new Queue(UInt((8 * pb).W), 4))
  private val next = RegInit(0.U((tileLog2 + 1).W))
  private val count = RegInit(0.U((tileLog2 + 1).W))
  private val inFlight = RegNext(io.read.valid, false.B)
  io.read.valid := busy && next =/= count && (pixels.io.count +& inFlight.asUInt) < 3.U
  io.read.bits := next(tileLog2 - 1, 0)
  when(io.read.valid) { next := next + 1.U }

  private val res = Seq.fill(Rgb.Channels)(Module(new FrameResolve(fa)))
  for ((r, ch) <- res.zipWithIndex) { r.io.sum := io.readOut.bits.sum(ch); r.io.scale := io.scale }
  private val values = res.map(r => Mux(io.readOut.bits.bad, fmt.quietNaN.U(fmt.width.W), r.io.out))
  pixels.io.enq.valid := io.readOut.valid && busy
  pixels.io.enq.bits := Cat(0.U((8 * slot).W) +: values.reverse.map(_.pad(8 * slot)))

  // Laying records into beats, one chunk a cycle.
  private val part = RegInit(0.U(log2Ceil(perPixel + 1).W))
  private val pos = RegInit(0.U(log2Ceil(perBeat + 1).W))
  private val buf = Reg(Vec(perBeat, UInt((8 * chunk).W)))
  private val filled = RegInit(VecInit(Seq.fill(perBeat)(false.B)))
  private val laid = RegInit(0.U((tileLog2 + 1).W))
  private val beats = Module(new Queue(new Axi4W(ap), 4))
  private val chunks = pixels.io.deq.bits.asTypeOf(Vec(perPixel, UInt((8 * chunk).W)))
  private val lastChunk = part === (perPixel - 1).U
  private val lastOfPass = lastChunk && laid === count - 1.U
  private val beatFull = pos === (perBeat - 1).U || lastOfPass
  private val canLay = pixels.io.deq.valid && (!beatFull || beats.io.enq.ready)
  pixels.io.deq.ready := canLay && lastChunk
  private val nowBuf = VecInit(buf.zipWithIndex.map { case (x, i) => Mux(pos === i.U, chunks(part), x) })
  private val nowFilled = VecInit(filled.zipWithIndex.map { case (x, i) => x || pos === i.U })
  beats.io.enq.valid := canLay && beatFull
  beats.io.enq.bits.data := nowBuf.asUInt
  beats.io.enq.bits.strb := VecInit(nowFilled.flatMap(f => Seq.fill(chunk)(f))).asUInt
  beats.io.enq.bits.last := false.B
  when(canLay) {
    part := Mux(lastChunk, 0.U, part + 1.U)
    when(lastChunk) { laid := laid + 1.U }
    when(beatFull) {
      pos := 0.U
      filled := VecInit(Seq.fill(perBeat)(false.B))
    }.otherwise {
      pos := pos + 1.U
      buf(pos) := chunks(part)
      filled(pos) := true.B
    }
  }

  // Bursts: AW first, then its beats; one B each.
  private val addr = Reg(UInt(ap.addrBits.W))
  private val awLeft = RegInit(0.U((tileLog2 + 2).W))
  private val toPage = (4096.U - addr(11, 0)) >> log2Ceil(db)
  private val burstBeats = Seq(16.U, awLeft, toPage).reduce((a, b) => Mux(a < b, a, b))
  private val lens = Module(new Queue(UInt(8.W), 4))
  private val bLeft = RegInit(0.U(log2Ceil(FrameWriter.MaxWrites + 1).W))
  io.aw.valid := busy && awLeft =/= 0.U && lens.io.enq.ready && bLeft < FrameWriter.MaxWrites.U
  io.aw.bits := 0.U.asTypeOf(io.aw.bits)
  io.aw.bits.addr := addr
  io.aw.bits.len := burstBeats - 1.U
  io.aw.bits.size := ap.sizeCode.U
  io.aw.bits.burst := mapm.axi.Axi4.BurstIncr
  io.aw.bits.cache := "b0011".U
  lens.io.enq.valid := io.aw.fire
  lens.io.enq.bits := burstBeats - 1.U
  when(io.aw.fire) { addr := addr + (burstBeats << log2Ceil(db)); awLeft := awLeft - burstBeats }
  private val beat = RegInit(0.U(8.W))
  io.w.valid := beats.io.deq.valid && lens.io.deq.valid
  io.w.bits := beats.io.deq.bits
  io.w.bits.last := beat === lens.io.deq.bits
  beats.io.deq.ready := io.w.ready && lens.io.deq.valid
  lens.io.deq.ready := io.w.fire && io.w.bits.last
  when(io.w.fire) { beat := Mux(io.w.bits.last, 0.U, beat + 1.U) }
  io.b.ready := true.B
  when(io.b.fire && io.b.bits.resp(1)) { error := true.B }
  bLeft := bLeft + io.aw.fire.asUInt - io.b.fire.asUInt

  when(io.start) {
    busy := true.B
    done := false.B
    error := false.B
    next := 0.U
    count := io.pixelCount
    laid := 0.U
    part := 0.U
    pos := ((first & (db - 1).U) >> log2Ceil(chunk))(log2Ceil(perBeat + 1) - 1, 0)
    filled := VecInit(Seq.fill(perBeat)(false.B))
    addr := down(first)
    awLeft := beatsTotal
    beat := 0.U
  }.elsewhen(busy && awLeft === 0.U && bLeft === 0.U && laid === count && !beats.io.deq.valid) {
    busy := false.B
    done := true.B
  }
  io.busy := busy
  io.done := done
  io.error := error
}

object FrameWriter {
  /** Write bursts outstanding at once (AW taken, B not yet). */
  val MaxWrites: Int = 8

  /** Bytes of a pixel's record in the frame buffer: four value slots (r, g, b, 0). */
  def pixelBytes(p: MapmParams): Int = 4 * p.slotBytes
}
