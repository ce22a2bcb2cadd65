package mapm.memory

import chisel3._
import chisel3.util._
import chisel3.experimental.hierarchy.{instantiable, public}
import mapm.util.{CostBlock, Counters}

/** One set of the tag array: a valid bit and a tag per way, and the set's pseudo-LRU state. */
class TagRow(cfg: CacheConfig) extends Bundle {
  val valid = UInt(cfg.ways.W)
  val tags = Vec(cfg.ways, UInt(cfg.tagBits.W))
  val plru = UInt(cfg.plruBits.W)
}

/** An access waiting for the lookup: its word address (the byte address without the offset in
  * the word) and the client's id. */
class CacheAccess(wordAddrBits: Int, idBits: Int) extends Bundle {
  val wordAddr = UInt(wordAddrBits.W)
  val id = UInt(idBits.W)
}

/** A cache's hit and miss of the lookup a cycle before ([[ReadOnlyCache.EventLatency]]), for
  * counters kept above it. */
class CacheEvents extends Bundle {
  /** An access whose line was present or already being refilled. */
  val hit = Bool()
  /** An access that allocated a line. */
  val miss = Bool()
}

/** Hit, miss and traffic counters of a cache. */
class CacheCounters(bits: Int) extends Bundle {
  /** Accesses whose line was present or already being refilled. */
  val hits = UInt(bits.W)
  /** Accesses that allocated a line (each fetches one line from below). */
  val misses = UInt(bits.W)
  /** Bytes received from the lower port. */
  val bytesFetched = UInt(bits.W)
}

/** A read-only, set-associative, non-blocking cache (3.2: the MAPM's caches never write back).
  *
  * Clients read one `wordBytes` word per request on `up` (a single-beat [[MemPort]] whose id is the
  * client's opaque tag); misses refill whole lines through `down`. The lower port of one cache has
  * the shape of the upper port of a cache whose word is this cache's line, so an L1 (with
  * `downBytes = lineBytes`) chains straight into an L2 built with [[CacheConfig.below]].
  *
  * Structure: the tag array (one [[TagRow]] per set) and the data array (one line per row, written
  * beat by beat) are `SyncReadMem`s. Accesses are looked up strictly in arrival order, one per
  * cycle, and each updates the tags and replacement state at lookup, so hit and miss counts are
  * those of an in-order cache of the same geometry whatever the memory latency:
  *  - hit on a present line: the data array is read the next cycle;
  *  - hit on a line still being refilled (a secondary miss, counted as a hit): the access waits in
  *    the [[MissTable]] and is served after the line's last beat;
  *  - miss: the victim is the lowest invalid way, else the tree pseudo-LRU way ([[TreePlru]]); the
  *    new tag is written at once, an MSHR fetches the line and the access waits on it.
  * The set index is the line address modulo the set count (above the bank bits of an interleaved
  * bank, [[CacheConfig.interleave]]), or hashed ([[CacheConfig.hashed]]).
  * The lookup stalls (in order) when the victim way is still held by an MSHR, when no MSHR or
  * target slot is free, or when a hit finds the data read port or the response queue taken. Waiting
  * accesses whose line has arrived have priority for the data read port. A response-queue credit
  * (queue entries plus the read in flight) keeps every data read a place in the queue, so response
  * backpressure only stalls, never drops.
  *
  * After reset the cache clears its tag array, one set per cycle (`up.req.ready` stays low).
  * Requests enter through a two-entry flow-through queue whose `ready` is a register's
  * ([[RegFifo]]): a request reaches the lookup in the cycle it arrives when the lookup is free,
  * and up to two wait there while it stalls, so no client logic depends on the lookup's outcome.
  *
  * Latency: a hit's response is valid 3 cycles after its request is accepted (lookup, data read,
  * response register). A miss's response is valid 5 + B + L cycles after acceptance without
  * contention, B the beats of a line on `down` and L the cycles the lower level waits beyond
  * answering the cycle after it takes the request (lookup, request issue, the beats, then the
  * waiting access's data read and response register); an L1 miss that hits an L2 built by
  * [[CacheConfig.below]] thus takes 8 cycles. Throughput: one request per cycle while hits flow
  * and the client takes responses; responses to different ids may leave out of order.
  */
@instantiable
class ReadOnlyCache(val cfg: CacheConfig) extends Module {
  override def desiredName = cfg.name
  CostBlock.tag(this, CostBlock.Caches)
  private val respDepth = 3
  private val setW = cfg.setBits max 1

  @public val io = IO(new Bundle {
    /** Client reads (the cache is the responder). */
    val up = Flipped(new MemPort(cfg.up))
    /** Line refills from the level below (the cache is the requester). */
    val down = new MemPort(cfg.down)
    val counters = Output(new CacheCounters(cfg.counterBits))
    val events = Output(new CacheEvents)
    /** Sticky: a request was not aligned to the word or asked for more than one beat (the cache
      * served the word holding its address), or a refill beat came that no miss waits for
      * ([[MissTable]]: an unknown id, a duplicate response, `last` on the wrong beat; dropped). */
    val protocolError = Output(Bool())
  })

  // Accesses are kept as word addresses (the byte address without its offset in the word).
  private val wordOff = log2Ceil(cfg.wordBytes)
  private val lineWordBits = cfg.lineOffsetBits - wordOff
  private def wordAddr(byteAddr: UInt): UInt = byteAddr(cfg.addressBits - 1, wordOff)
  private val bk = cfg.bankBits
  private def setOf(wa: UInt): UInt =
    if (cfg.setBits == 0) 0.U(1.W)
    else if (!cfg.hashed) wa(lineWordBits + bk + cfg.setBits - 1, lineWordBits + bk)
    else {
      // XOR of the set-index-wide chunks of the line address (CacheConfig.hashed).
      val line = wa(cfg.addressBits - wordOff - 1, lineWordBits)
      val chunks = (0 until line.getWidth by cfg.setBits).map(lo => line((lo + cfg.setBits - 1) min (line.getWidth - 1), lo))
      chunks.reduce(_ ^ _)
    }
  // The line address without its set bits (with bank bits, those below the set index).
  private def tagOf(wa: UInt): UInt =
    if (bk == 0 || cfg.hashed) wa(cfg.addressBits - wordOff - 1, lineWordBits + cfg.setBits)
    else Cat(wa(cfg.addressBits - wordOff - 1, lineWordBits + bk + cfg.setBits), wa(lineWordBits + bk - 1, lineWordBits))
  private def wordOf(wa: UInt): UInt = if (lineWordBits == 0) 0.U(0.W) else wa(lineWordBits - 1, 0)
  private def rowOf(set: UInt, way: UInt): UInt =
    if (cfg.sets == 1) way else if (cfg.ways == 1) set else Cat(set, way)

  val tagMem = SyncReadMem(1 << setW, new TagRow(cfg))
  val dataMem = SyncReadMem(cfg.hw.lines, Vec(cfg.beatsPerLine, UInt(cfg.down.dataBits.W)))
  val miss = Module(new MissTable(cfg))
  io.down <> miss.io.down

  // Reset sweep: clear every set's valid bits and replacement state.
  val clearing = RegInit(true.B)
  val clearSet = RegInit(0.U(setW.W))

  // Lookup stage (s1): the access accepted last cycle, and the row read for it.
  val s1Valid = RegInit(false.B)
  val s1Addr = Reg(UInt((cfg.addressBits - wordOff).W))
  val s1Id = Reg(UInt(cfg.idBits.W))
  val s1Done = Wire(Bool())
  val s1Set = setOf(s1Addr)

  // Requests pass a two-entry flow-through queue whose ready is a register's, so that no client
  // waits on this cycle's lookup (its tag compare and miss table) to decide what to send.
  val inQ = Module(new RegFifo(new CacheAccess(cfg.addressBits - wordOff, cfg.idBits), 2, flow = true))
  inQ.io.enq.valid := io.up.req.valid && !clearing
  inQ.io.enq.bits.wordAddr := wordAddr(io.up.req.bits.addr)
  inQ.io.enq.bits.id := io.up.req.bits.id
  io.up.req.ready := inQ.io.enq.ready && !clearing
  val req = inQ.io.deq
  req.ready := !s1Valid || s1Done
  when(req.fire) {
    s1Addr := req.bits.wordAddr
    s1Id := req.bits.id
  }
  s1Valid := req.fire || (s1Valid && !s1Done)
  val badRequest = io.up.req.bits.len =/= 0.U ||
    (if (wordOff == 0) false.B else io.up.req.bits.addr(wordOff - 1, 0) =/= 0.U)
  val protocolError = RegInit(false.B)
  when(io.up.req.fire && badRequest) { protocolError := true.B }
  io.protocolError := protocolError || miss.io.protocolError

  // A stalled lookup rereads its own set, so the row it sees is never older than one write.
  val readSet = Mux(s1Valid && !s1Done, s1Set, setOf(req.bits.wordAddr))
  val memRow = tagMem.read(readSet)
  // The row written last cycle is forwarded when the lookup is on that set (read-during-write).
  val lastWrite = RegInit(false.B)
  val lastSet = Reg(UInt(setW.W))
  val lastRow = Reg(new TagRow(cfg))
  val row = Mux(lastWrite && lastSet === s1Set, lastRow, memRow)

  val s1Tag = tagOf(s1Addr)
  val hitVec = VecInit((0 until cfg.ways).map(w => row.valid(w) && row.tags(w) === s1Tag)).asUInt
  val hit = hitVec.orR
  val hitWay = OHToUInt(hitVec)
  val invalid = ~row.valid
  val victim = Mux(invalid.orR, PriorityEncoder(invalid), TreePlru.victim(row.plru, cfg.ways))
  miss.io.set := s1Set
  miss.io.hitWay := hitWay
  miss.io.victimWay := victim
  val pendingHit = hit && miss.io.hitPending

  // The data read port: waiting accesses first, then this cycle's hit.
  val s2Valid = RegInit(false.B)
  val respQ = Module(new RegFifo(new MemResp(cfg.up), respDepth))
  val credit = respQ.io.count +& s2Valid < respDepth.U
  val drainGo = miss.io.drain.valid && credit
  miss.io.drain.ready := credit
  val hitGo = s1Valid && hit && !pendingHit && credit && !miss.io.drain.valid
  val parkGo = s1Valid && pendingHit && miss.io.canPark
  val allocGo = s1Valid && !hit && miss.io.canAlloc && miss.io.canPark && !miss.io.victimLocked
  s1Done := hitGo || parkGo || allocGo

  miss.io.alloc := allocGo
  miss.io.lineAddr := s1Addr(cfg.addressBits - wordOff - 1, lineWordBits)
  miss.io.park.valid := parkGo || allocGo
  miss.io.park.bits.mshr := Mux(allocGo, miss.io.allocMshr, miss.io.hitMshr)
  miss.io.park.bits.word := wordOf(s1Addr)
  miss.io.park.bits.id := s1Id

  // Tag array writes: the reset sweep, then one row per finished lookup (new tag and/or LRU state).
  val touchedWay = Mux(hit, hitWay, victim)
  val newRow = Wire(new TagRow(cfg))
  newRow.valid := row.valid | UIntToOH(touchedWay, cfg.ways)
  newRow.tags := VecInit(row.tags.zipWithIndex.map { case (t, w) => Mux(!hit && victim === w.U, s1Tag, t) })
  newRow.plru := TreePlru.touch(row.plru, cfg.ways, touchedWay)
  when(clearing) {
    clearSet := clearSet + 1.U
    when(clearSet === ((1 << setW) - 1).U) { clearing := false.B }
  }
  when(clearing || s1Done) {
    tagMem.write(Mux(clearing, clearSet, s1Set), Mux(clearing, 0.U.asTypeOf(new TagRow(cfg)), newRow))
  }
  lastWrite := s1Done
  lastSet := s1Set
  lastRow := newRow

  // Refill beats.
  when(miss.io.fill.valid) {
    val beats = VecInit(Seq.fill(cfg.beatsPerLine)(miss.io.fill.bits.data))
    dataMem.write(miss.io.fill.bits.row, beats, UIntToOH(miss.io.fill.bits.beat, cfg.beatsPerLine).asBools)
  }

  // Data read (s2) and the response queue.
  val readRow = Mux(miss.io.drain.valid, miss.io.drain.bits.row, rowOf(s1Set, hitWay))
  val line = dataMem.read(readRow, drainGo || hitGo)
  s2Valid := drainGo || hitGo
  val s2Word = RegNext(Mux(miss.io.drain.valid, miss.io.drain.bits.word, wordOf(s1Addr)))
  val s2Id = RegNext(Mux(miss.io.drain.valid, miss.io.drain.bits.id, s1Id))
  respQ.io.enq.valid := s2Valid
  private val words = line.asTypeOf(Vec(cfg.wordsPerLine, UInt(cfg.up.dataBits.W)))
  respQ.io.enq.bits.data := (if (cfg.wordsPerLine == 1) words(0) else words(s2Word))
  respQ.io.enq.bits.id := s2Id
  respQ.io.enq.bits.last := true.B
  io.up.resp <> respQ.io.deq

  // Registered: the lookup's outcome is this part's longest logic, and the counters live above it.
  io.events.hit := RegNext(s1Done && hit, false.B)
  io.events.miss := RegNext(allocGo, false.B)
  io.counters.hits := Counters.count(Seq(io.events.hit), cfg.counterBits)
  io.counters.misses := Counters.count(Seq(io.events.miss), cfg.counterBits)
  io.counters.bytesFetched := Counters.accumulate(Mux(io.down.resp.fire, cfg.downBytes.U, 0.U), cfg.counterBits)
}

object ReadOnlyCache {
  /** Cycles from a lookup to its hit or miss on `events`. */
  val EventLatency = 1
}
