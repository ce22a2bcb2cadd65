package mapm.soc

import chisel3._
import chisel3.util._
import mapm.format.MemoryLayout
import mapm.memory.{MemPort, MemPortParams}
import mapm.params.{MapmParams, QueryIn}
import mapm.util.Index

/** Reads the query stream (docs/memory-layout.md: 4-byte query indices from `streamBase`) and
  * hands its entries to the MAPM in order, one a cycle: the coprocessor's tree-search instructions.
  * Without `useStream` (QUERY_ORDER.stream 0, taken at `start`) it reads nothing and hands over
  * the indices 0 .. `queryCount` - 1 in order: the host wrote the records in the order to run.
  *
  * It reads whole 64-byte lines (16 entries; the stream array is padded to a line), up to
  * `streamLines` ahead, each into a line buffer of its own under the buffer's id, so lines may come
  * back in any order; entries leave in stream order. An entry whose index is not below
  * `queryCount` is skipped and sets the sticky `badQuery`. `done` rises once every entry of the
  * `queryCount` has been handed over or skipped.
  *
  * Latency: the memory's, then one cycle. Throughput: one entry a cycle.
  */
class StreamReader(p: MapmParams) extends Module {
  private val lines = p.coproc.streamLines
  private val db = p.memory.dataBytes
  private val lineBytes = MemoryLayout.Alignment
  private val beatsPerLine = lineBytes / db
  private val perBeat = db / 4
  private val perLine = lineBytes / 4
  require(db >= 4 && lineBytes % db == 0, s"$db-byte beats")
  val memParams: MemPortParams = StreamReader.memParams(p)
  override def desiredName = s"StreamReader_l${lines}_d$db"

  val io = IO(new Bundle {
    val start = Input(Bool())
    val useStream = Input(Bool())
    val streamBase = Input(UInt(p.memory.addressBits.W))
    val queryCount = Input(UInt(32.W))
    val mem = new MemPort(memParams)
    val out = Decoupled(new QueryIn(p))
    val done = Output(Bool())
    val badQuery = Output(Bool())
  })

  private val running = RegInit(false.B)
  private val fromStream = RegInit(false.B)
  private val count = RegInit(0.U(32.W))
  private val totalLines = (count + (perLine - 1).U) >> log2Ceil(perLine)
  private val issued = RegInit(0.U(32.W))  // lines asked for
  private val head = RegInit(0.U(32.W))    // the line entries leave from
  private val entry = RegInit(0.U(log2Ceil(perLine).W))
  private val taken = RegInit(0.U(32.W))   // entries handed over or skipped
  private val bad = RegInit(false.B)

  private val buf = Reg(Vec(lines, Vec(beatsPerLine, UInt((8 * db).W))))
  private val arrived = RegInit(VecInit(Seq.fill(lines)(VecInit(Seq.fill(beatsPerLine)(false.B)))))
  private val beatIn = RegInit(VecInit(Seq.fill(lines)(0.U(log2Ceil(beatsPerLine + 1).W))))
  private def slotOf(line: UInt): UInt = if (lines == 1) 0.U else if (isPow2(lines)) line(log2Ceil(lines) - 1, 0) else line % lines.U

  // Requests: the next line, while it is in the stream and its buffer is free (lines ahead of the head).
  io.mem.req.valid := running && fromStream && issued < totalLines && issued - head < lines.U
  io.mem.req.bits.addr := io.streamBase + (issued << log2Ceil(lineBytes))
  io.mem.req.bits.id := slotOf(issued)
  io.mem.req.bits.len := (beatsPerLine - 1).U
  when(io.mem.req.fire) { issued := issued + 1.U }

  io.mem.resp.ready := true.B
  when(io.mem.resp.fire) {
    val s = io.mem.resp.bits.id
    buf(s)(beatIn(s)) := io.mem.resp.bits.data
    arrived(s)(beatIn(s)) := true.B
    beatIn(s) := Mux(io.mem.resp.bits.last, 0.U, beatIn(s) + 1.U)
  }

  // Entries leave in order from the head line.
  private val hs = slotOf(head)
  private val beat = entry >> log2Ceil(perBeat)
  private val word = if (perBeat == 1) 0.U else entry(log2Ceil(perBeat) - 1, 0)
  private val have = running && taken < count && (arrived(hs)(beat) || !fromStream)
  private val q = Mux(fromStream, (buf(hs)(beat) >> (word << 5))(31, 0), taken)
  private val fits = q < count
  io.out.valid := have && fits
  io.out.bits.q := q(p.indices.queryBits - 1, 0)
  private val step = (have && !fits) || io.out.fire
  when(have && !fits) { bad := true.B }
  when(step) {
    taken := taken + 1.U
    val lineEnd = entry === (perLine - 1).U || taken === count - 1.U
    entry := Mux(lineEnd, 0.U, entry + 1.U)
    when(lineEnd) {
      head := head + 1.U
      arrived(hs) := VecInit(Seq.fill(beatsPerLine)(false.B))
    }
  }

  when(io.start) {
    running := true.B
    fromStream := io.useStream
    count := io.queryCount
    issued := 0.U
    head := 0.U
    entry := 0.U
    taken := 0.U
    bad := false.B
    for (s <- 0 until lines) arrived(s) := VecInit(Seq.fill(beatsPerLine)(false.B))
  }.elsewhen(running && taken === count) { running := false.B }
  io.done := !running && taken === count
  io.badQuery := bad
}

object StreamReader {
  /** The reader's memory port: whole 64-byte lines, one id per line buffer. */
  def memParams(p: MapmParams): MemPortParams =
    MemPortParams(p.memory.addressBits, p.memory.dataBytes, Index.bits(p.coproc.streamLines), MemoryLayout.Alignment / p.memory.dataBytes)
}

