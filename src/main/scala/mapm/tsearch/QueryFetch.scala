package mapm.tsearch

import chisel3._
import chisel3.util._
import mapm.memory.{CacheConfig, CacheCounters, MemPort, ReadOnlyCache}
import mapm.params.{MapmParams, QueryData, QueryHwRecord, QueryIn, Records, Rgb}
import mapm.util.Pick

/** The front of the TS block: takes the host's tree-search instructions (query position and
  * index, 3.2) and reads each query's contribution (r, g, b), the first 16 bytes of its 32-byte
  * query record, through the SOQ cache, so that the search and every SO it yields carry it
  * (docs/mapm.md, "Where the query data travels"). A record whose padding (the slots' upper bits,
  * bytes 12..15) is not zero raises the sticky `error`.
  *
  * Up to `queryFetches` queries are in flight, each in a slot of its own; a query leaves on `out`
  * once its record has arrived, round-robin among the arrived ones, so a record the memory
  * answers late does not hold back the queries behind it. Record layout
  * (docs/memory-layout.md): contribution c in the 4-byte slot at byte 4c.
  *
  * Latency: SOQ hit latency (3) + 1 cycles from `in` to `out`. Throughput: one query per cycle.
  */
class QueryFetch(p: MapmParams) extends Module {
  private val n = p.queues.queryFetches
  private val w = p.numbers.format.width
  val soqConfig: CacheConfig = QueryFetch.soqConfig(p)
  require(Records.query.fields.forall(f => f.name.startsWith("contrib_") || f.offset >= Records.queryHwBytes),
    s"QueryFetch checks that the ${Records.queryHwBytes} bytes it reads hold the contribution and zeros, but the query record has another field among them")
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
  soq.io.up.req.bits.addr := io.queryBase + (io.in.bits.q << Records.indexShift(Records.query))
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
  private val rec = soq.io.up.resp.bits.data.asTypeOf(new QueryHwRecord(Records.SlotBytes, w))
  when(soq.io.up.resp.fire) {
    val i = soq.io.up.resp.bits.id
    arrived(i) := true.B
    for (c <- 0 until Rgb.Channels) held(i).contrib(c) := rec.contrib(c).value
  }
  // The rest of the bytes read must be zero: the slots' upper bits and the bytes after the contribution.
  private val padding = rec.contrib.filter(_ => w < 8 * Records.SlotBytes).map(_.pad) :+ rec.rest
  private val malformed = RegInit(false.B)
  when(soq.io.up.resp.fire && padding.map(_.orR).reduce(_ || _)) { malformed := true.B }
  // Arrived queries leave round-robin from the slot after the last one out (records come back in
  // any order; a late one does not hold back the others).
  val rrNext = RegInit(0.U(Pick.bits(n).W))
  private val (any, head) = Pick.roundRobin(valid.asUInt & arrived.asUInt, rrNext)
  io.out.valid := any
  io.out.bits := held(head)
  when(io.out.fire) { valid(head) := false.B; rrNext := Pick.next(head, n) }

  io.error := soq.io.protocolError || malformed
  io.idle := !valid.asUInt.orR
  io.waiting := (valid.asUInt & ~arrived.asUInt).orR
}

object QueryFetch {
  /** The SOQ cache: Table 4.2's geometry, the part of a query record the hardware reads (16 bytes) per read, fetched from memory
    * in the port's beats. Every query misses once (its record is read once), so the cache keeps
    * as many misses in flight as there are query fetches (up to its 64 MSHRs): at 100 cycles of
    * memory latency, 4 MSHRs would hold the stream to 0.04 queries per cycle. */
  def soqConfig(p: MapmParams): CacheConfig = {
    val n = p.queues.queryFetches
    CacheConfig(p.caches.soq, wordBytes = Records.queryHwBytes, idBits = Pick.bits(n), addressBits = p.memory.addressBits,
      downBytes = p.memory.dataBytes, mshrs = n min 64, targets = n min 64)
  }
}
