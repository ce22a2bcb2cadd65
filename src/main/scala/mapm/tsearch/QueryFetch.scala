package mapm.tsearch

import chisel3._
import chisel3.util._
import mapm.memory.{CacheConfig, CacheEvents, MemPort, ReadOnlyCache}
import mapm.params.{MapmParams, QueryData, QueryIn, QueryRecord, Records, Rgb}
import mapm.uncore.Shapes
import mapm.util.{Index, RoundRobin}

/** The front of the TS block: takes the tree-search instructions (query indices, 3.2) and reads
  * each query's record through the SOQ cache, so that the search has its position and every SO
  * it yields carries its contribution (r, g, b) and pixel (docs/mapm.md, "Where the query data
  * travels"). A record whose padding (the slots' upper bits, the unused bytes) is not zero, or
  * whose pixel index does not fit `pixelBits`, raises the sticky `error`.
  *
  * Up to `queryFetches` queries are in flight, each in a slot of its own; a query leaves on `out`
  * once its record has arrived, round-robin among the arrived ones, so a record the memory
  * answers late does not hold back the queries behind it. Record layout
  * (docs/memory-layout.md): contribution c in the slot at byte c * slot.
  *
  * Latency: SOQ hit latency (3) + 1 cycles from `in` to `out`. Throughput: one query per cycle.
  */
class QueryFetch(p: MapmParams) extends Module {
  private val n = p.queues.queryFetches
  private val w = p.numbers.format.width
  private val records = p.records
  val soqConfig: CacheConfig = Shapes(p).soq
  override def desiredName = s"QueryFetch_$n"

  val io = IO(new Bundle {
    val queryBase = Input(UInt(p.memory.addressBits.W))
    val in = Flipped(Decoupled(new QueryIn(p)))
    val out = Decoupled(new QueryData(p))
    val mem = new MemPort(soqConfig.down)
    /** No query is held. */
    val idle = Output(Bool())
    /** A query is held whose record has not arrived. */
    val waiting = Output(Bool())
    val soq = Output(new CacheEvents)
    val error = Output(Bool())
  })

  val soq = Module(new ReadOnlyCache(soqConfig))
  io.mem <> soq.io.down
  io.soq := soq.io.events

  val held = Reg(Vec(n, new QueryData(p)))
  val valid = RegInit(VecInit(Seq.fill(n)(false.B)))
  val arrived = RegInit(VecInit(Seq.fill(n)(false.B)))
  private val tail = PriorityEncoder(~valid.asUInt)
  private val room = !valid.asUInt.andR
  io.in.ready := room && soq.io.up.req.ready
  soq.io.up.req.valid := io.in.valid && room
  soq.io.up.req.bits.addr := io.queryBase + (io.in.bits.q << Records.indexShift(records.query))
  soq.io.up.req.bits.id := tail
  soq.io.up.req.bits.len := 0.U
  when(io.in.fire) {
    valid(tail) := true.B
    arrived(tail) := false.B
    held(tail).q := io.in.bits.q
  }
  soq.io.up.resp.ready := true.B
  private val rec = soq.io.up.resp.bits.data.asTypeOf(new QueryRecord(records.slot, w))
  when(soq.io.up.resp.fire) {
    val i = soq.io.up.resp.bits.id
    arrived(i) := true.B
    for (c <- 0 until Rgb.Channels) held(i).contrib(c) := rec.contrib(c).value
    held(i).x := rec.pos(0).value
    held(i).y := rec.pos(1).value
    held(i).z := rec.pos(2).value
    held(i).pixel := rec.pixel
  }
  // The slots' upper bits, the unused bytes and the pixel's bits above pixelBits must be zero.
  private val padding = (rec.contrib ++ rec.pos).filter(_ => w < 8 * records.slot).map(_.pad)
  private val unused = Seq(rec.gap, rec.tail).filter(_.getWidth > 0) ++
    (if (p.indices.pixelBits < 32) Seq(rec.pixel(31, p.indices.pixelBits)) else Nil)
  private val malformed = RegInit(false.B)
  when(soq.io.up.resp.fire && (padding ++ unused).map(_.orR).reduce(_ || _)) { malformed := true.B }
  // Arrived queries leave round-robin from the slot after the last one out (records come back in
  // any order; a late one does not hold back the others).
  val rrNext = RegInit(0.U(Index.bits(n).W))
  private val (any, head) = RoundRobin.first(valid.asUInt & arrived.asUInt, rrNext)
  io.out.valid := any
  io.out.bits := held(head)
  when(io.out.fire) { valid(head) := false.B; rrNext := Index.next(head, n) }

  io.error := soq.io.protocolError || malformed
  io.idle := !valid.asUInt.orR
  io.waiting := (valid.asUInt & ~arrived.asUInt).orR
}
