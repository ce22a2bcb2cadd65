package mapm.tsearch

import chisel3._
import chisel3.util._
import mapm.memory.{CacheConfig, CacheCounters, MemPort, ReadOnlyCache}
import mapm.params.{MapmParams, QueryData, QueryHwRecord, QueryIn, Records, Rgb}
import mapm.uncore.Shapes
import mapm.util.{Index, RoundRobin}

/** The front of the TS block: takes the host's tree-search instructions (query position and
  * index, 3.2) and reads each query's contribution (r, g, b), the first
  * [[mapm.format.MemoryLayout.queryHwBytes]] bytes of its query record (16 of 32 with 4-byte
  * slots), through the SOQ cache, so that the search and every SO it yields carry it
  * (docs/mapm.md, "Where the query data travels"). A record whose padding (the slots' upper bits,
  * and the reserved gap after the contribution) is not zero, or, with 2-byte slots, whose position
  * x (read with the contribution) is not the x the host sent, raises the sticky `error`.
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
    val soq = Output(new CacheCounters(soqConfig.counterBits))
    val error = Output(Bool())
  })

  val soq = Module(new ReadOnlyCache(soqConfig))
  io.mem <> soq.io.down
  io.soq := soq.io.counters

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
    held(tail).x := io.in.bits.x
    held(tail).y := io.in.bits.y
    held(tail).z := io.in.bits.z
    held(tail).q := io.in.bits.q
  }
  soq.io.up.resp.ready := true.B
  private val rec = soq.io.up.resp.bits.data.asTypeOf(new QueryHwRecord(records.slot, w))
  when(soq.io.up.resp.fire) {
    val i = soq.io.up.resp.bits.id
    arrived(i) := true.B
    for (c <- 0 until Rgb.Channels) held(i).contrib(c) := rec.contrib(c).value
  }
  // The slots' upper bits must be zero; the bytes after the contribution too (a reserved gap), or
  // with 2-byte slots they are position x's slot, which must be the x the host sent.
  private val padding = rec.contrib.filter(_ => w < 8 * records.slot).map(_.pad)
  private val restBad = if (records.queryGapReserved) rec.rest.orR else rec.rest =/= held(soq.io.up.resp.bits.id).x.pad(rec.rest.getWidth)
  private val malformed = RegInit(false.B)
  when(soq.io.up.resp.fire && (padding.map(_.orR) :+ restBad).reduce(_ || _)) { malformed := true.B }
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
