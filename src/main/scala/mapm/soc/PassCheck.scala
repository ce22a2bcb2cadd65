package mapm.soc

import chisel3._
import chisel3.util._
import mapm.format.MemoryLayout
import mapm.params.MapmParams

/** What is wrong with a frame pass's configuration before it starts (docs/coprocessor.md, the
  * ERROR_CAUSE bits of the same names): `align`, an array base not a multiple of 64 bytes;
  * `empty`, no query or no pixel; `limit`, a count beyond the hardware's index widths or tile, a
  * pixel beyond the pixel index width, or an array beyond the address width; `overlap`, two of the
  * node, photon, query, stream and frame arrays sharing a byte. The stream array counts only when
  * the pass reads it (`useStream`). Combinational.
  */
class PassCheck(p: MapmParams) extends Module {
  override def desiredName = s"PassCheck_s${p.slotBytes}_a${p.memory.addressBits}"
  val io = IO(new Bundle {
    val config = Input(new PassConfig)
    val align = Output(Bool())
    val empty = Output(Bool())
    val limit = Output(Bool())
    val overlap = Output(Bool())
  })
  private val c = io.config
  private val r = p.records
  private val a = MemoryLayout.Alignment
  private val bases = Seq(true.B -> c.nodeBase, true.B -> c.photonBase, true.B -> c.queryBase, c.useStream -> c.streamBase, true.B -> c.frameBase)
  io.align := bases.map { case (used, b) => used && b(log2Ceil(a) - 1, 0).orR }.reduce(_ || _)
  io.empty := c.queryCount === 0.U || c.pixelCount === 0.U

  // Spans [start, end) in 66 bits: no sum can wrap.
  private def span(base: UInt, count: UInt, bytes: Int): (UInt, UInt) = (base.pad(66), base.pad(66) +& count * bytes.U)
  private val streamEnd = c.streamBase.pad(66) +& (((c.queryCount.pad(34) << 2) + (a - 1).U) & (~(a - 1).U(34.W)).asUInt)
  private val frameStart = c.frameBase.pad(66) +& c.pixelBase * FrameWriter.pixelBytes(p).U
  private val spans: Seq[(Bool, (UInt, UInt))] = Seq(
    (c.nodeCount =/= 0.U, span(c.nodeBase, c.nodeCount, r.node.bytes)),
    (c.nodeCount =/= 0.U, span(c.photonBase, c.nodeCount, r.photon.bytes)),
    (true.B, span(c.queryBase, c.queryCount, r.query.bytes)),
    (c.useStream, (c.streamBase.pad(66), streamEnd)),
    (true.B, (frameStart, frameStart +& c.pixelCount * FrameWriter.pixelBytes(p).U)))
  private val clash = for (i <- spans.indices; j <- spans.indices if i < j) yield {
    val (ui, (si, ei)) = spans(i)
    val (uj, (sj, ej)) = spans(j)
    ui && uj && si < ej && sj < ei
  }
  io.overlap := clash.reduce(_ || _)

  private val top = BigInt(1) << p.memory.addressBits
  io.limit := c.nodeCount > (BigInt(1) << p.indices.nodeBits).U || c.queryCount > (BigInt(1) << p.indices.queryBits).U ||
    c.pixelCount > (1 << p.coproc.tileLog2).U || (c.pixelBase +& c.pixelCount) > (BigInt(1) << p.indices.pixelBits).U ||
    spans.map { case (used, (_, e)) => used && e > top.U }.reduce(_ || _)
}
