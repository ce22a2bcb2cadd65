package mapm.memory

import chisel3._
import chisel3.util._

/** An access waiting for a line that is being refilled. */
class MissTarget(cfg: CacheConfig) extends Bundle {
  val mshr = UInt(cfg.mshrBits.W)
  /** Client word index within the line. */
  val word = UInt(cfg.wordIdxBits.W)
  val id = UInt(cfg.idBits.W)
}

/** A data-array read that serves a waiting access once its line has arrived. */
class MissDrain(cfg: CacheConfig) extends Bundle {
  val row = UInt(cfg.rowBits.W)
  val word = UInt(cfg.wordIdxBits.W)
  val id = UInt(cfg.idBits.W)
}

/** Miss handling of a [[ReadOnlyCache]]: the MSHRs (one per line being refilled), the table of
  * accesses waiting on them, the lower memory port and the refill writes.
  *
  * The cache's lookup stage allocates an MSHR for a miss (the line's set, the victim way it will
  * fill, its line address) and parks the missing access, or an access that hits a line still being
  * refilled, as a target of that MSHR. Requests go to the lower port in allocation order (a FIFO of
  * MSHR indices), so the lower level sees the misses in the order the cache decided them. Every
  * response beat is accepted at once (`down.resp.ready` is always high) and becomes a write of one
  * beat into the line's data-array row. When the last beat has arrived the line is filled: its
  * targets leave through `drain`, one per cycle, lowest table slot first, and the MSHR is freed when
  * none is left (the cycle after the last one drains). A way stays locked (no new line may be allocated into it) from allocation until the
  * MSHR is freed, which keeps refill writes and target reads off a reused row.
  *
  * Latency: a request leaves on `down.req` the cycle after allocation at the earliest; a target may
  * drain the cycle after its line's last beat.
  */
class MissTable(cfg: CacheConfig) extends Module {
  override def desiredName = s"MissTable_m${cfg.mshrs}_t${cfg.targets}_w${cfg.ways}"
  private val setW = cfg.setBits max 1

  val io = IO(new Bundle {
    /** The set being looked up and the ways the lookup asks about. */
    val set = Input(UInt(setW.W))
    val hitWay = Input(UInt(cfg.wayBits.W))
    val victimWay = Input(UInt(cfg.wayBits.W))
    /** `hitWay` of `set` is still being refilled, by MSHR `hitMshr`. */
    val hitPending = Output(Bool())
    val hitMshr = Output(UInt(cfg.mshrBits.W))
    /** `victimWay` of `set` is held by an MSHR and may not be replaced yet. */
    val victimLocked = Output(Bool())
    /** An MSHR and a target slot are free (allocation and parking are possible this cycle). */
    val canAlloc = Output(Bool())
    val canPark = Output(Bool())
    /** Allocate an MSHR for line `lineAddr` into `victimWay` of `set`; its index is `allocMshr`. */
    val alloc = Input(Bool())
    val lineAddr = Input(UInt((cfg.addressBits - cfg.lineOffsetBits).W))
    val allocMshr = Output(UInt(cfg.mshrBits.W))
    /** Park an access as a target of MSHR `park.bits.mshr`. */
    val park = Flipped(Valid(new MissTarget(cfg)))
    /** Waiting accesses whose line has arrived. */
    val drain = Decoupled(new MissDrain(cfg))
    /** One beat of refill data to write: row `fill.bits.row`, beat slot `fill.bits.beat`. */
    val fill = Valid(new Bundle {
      val row = UInt(cfg.rowBits.W)
      val beat = UInt(cfg.beatIdxBits.W)
      val data = UInt(cfg.down.dataBits.W)
    })
    val down = new MemPort(cfg.down)
    /** Sticky: a response beat no MSHR was waiting for (an unknown id, an id whose request has not
      * left, a beat after the line's last one, a duplicate response) or a `last` flag on the
      * wrong beat. The beat is dropped. */
    val protocolError = Output(Bool())
  })

  class Mshr extends Bundle {
    val valid = Bool()
    /** Its request has left on `down.req`. */
    val issued = Bool()
    val filled = Bool()
    val set = UInt(setW.W)
    val way = UInt(cfg.wayBits.W)
    val beat = UInt(cfg.beatIdxBits.W)
  }
  val mshrs = RegInit(VecInit(Seq.fill(cfg.mshrs)(0.U.asTypeOf(new Mshr))))
  val lineAddrs = Reg(Vec(cfg.mshrs, UInt((cfg.addressBits - cfg.lineOffsetBits).W)))
  val targets = Reg(Vec(cfg.targets, new MissTarget(cfg)))
  val targetValid = RegInit(VecInit(Seq.fill(cfg.targets)(false.B)))

  private def holds(m: Mshr, way: UInt) = m.valid && m.set === io.set && m.way === way
  val pendingHits = VecInit(mshrs.map(m => holds(m, io.hitWay) && !m.filled))
  io.hitPending := pendingHits.asUInt.orR
  io.hitMshr := OHToUInt(pendingHits)
  io.victimLocked := mshrs.map(holds(_, io.victimWay)).reduce(_ || _)

  val freeMshrs = VecInit(mshrs.map(!_.valid))
  io.canAlloc := freeMshrs.asUInt.orR
  io.allocMshr := PriorityEncoder(freeMshrs)
  val freeTargets = VecInit(targetValid.map(!_))
  io.canPark := freeTargets.asUInt.orR

  // Requests leave in allocation order.
  val issue = Module(new RegFifo(UInt(cfg.mshrBits.W), cfg.mshrs))
  issue.io.enq.valid := io.alloc
  issue.io.enq.bits := io.allocMshr
  io.down.req.valid := issue.io.deq.valid
  io.down.req.bits.addr := Cat(at(lineAddrs, issue.io.deq.bits), 0.U(cfg.lineOffsetBits.W))
  io.down.req.bits.id := issue.io.deq.bits
  io.down.req.bits.len := (cfg.beatsPerLine - 1).U
  issue.io.deq.ready := io.down.req.ready

  // Refill beats go straight into the data array; a beat no MSHR waits for is flagged and dropped.
  io.down.resp.ready := true.B
  val beatMshr = at(mshrs, io.down.resp.bits.id)
  private val knownId = if (isPow2(cfg.mshrs) && cfg.mshrBits == log2Ceil(cfg.mshrs)) true.B else io.down.resp.bits.id < cfg.mshrs.U
  private val lastBeat = beatMshr.beat === (cfg.beatsPerLine - 1).U
  val beatOk = knownId && beatMshr.valid && beatMshr.issued && !beatMshr.filled && io.down.resp.bits.last === lastBeat
  val protocolError = RegInit(false.B)
  when(io.down.resp.fire && !beatOk) { protocolError := true.B }
  io.protocolError := protocolError
  io.fill.valid := io.down.resp.valid && beatOk
  io.fill.bits.row := rowOf(beatMshr)
  io.fill.bits.beat := beatMshr.beat
  io.fill.bits.data := io.down.resp.bits.data

  // Targets of filled lines drain one per cycle.
  val drainable = VecInit(targets.zip(targetValid).map { case (t, v) => v && at(mshrs, t.mshr).filled })
  val drainSlot = PriorityEncoder(drainable)
  io.drain.valid := drainable.asUInt.orR
  val drainTarget = at(targets, drainSlot)
  io.drain.bits.row := rowOf(at(mshrs, drainTarget.mshr))
  io.drain.bits.word := drainTarget.word
  io.drain.bits.id := drainTarget.id

  for (m <- 0 until cfg.mshrs) {
    val waiting = targets.zip(targetValid).map { case (t, v) => v && t.mshr === m.U }.reduce(_ || _)
    val beatHere = io.down.resp.fire && beatOk && io.down.resp.bits.id === m.U
    when(io.down.req.fire && issue.io.deq.bits === m.U) { mshrs(m).issued := true.B }
    when(io.alloc && io.allocMshr === m.U) {
      mshrs(m).valid := true.B
      mshrs(m).issued := false.B
      mshrs(m).filled := false.B
      mshrs(m).set := io.set
      mshrs(m).way := io.victimWay
      mshrs(m).beat := 0.U
      lineAddrs(m) := io.lineAddr
    }.elsewhen(beatHere) {
      mshrs(m).beat := mshrs(m).beat + 1.U
      when(io.down.resp.bits.last) { mshrs(m).filled := true.B }
    }.elsewhen(mshrs(m).filled && !waiting) {
      mshrs(m).valid := false.B
    }
  }

  val parkSlot = PriorityEncoder(freeTargets)
  for (t <- 0 until cfg.targets) {
    when(io.park.valid && parkSlot === t.U) {
      targetValid(t) := true.B
      targets(t) := io.park.bits
    }.elsewhen(io.drain.fire && drainSlot === t.U) {
      targetValid(t) := false.B
    }
  }

  /** `v(i)`, also for a one-element `v` (whose index is a 1-bit zero). */
  private def at[T <: Data](v: Vec[T], i: UInt): T = if (v.length == 1) v(0) else v(i)

  private def rowOf(m: Mshr): UInt =
    if (cfg.sets == 1) m.way
    else if (cfg.ways == 1) m.set
    else Cat(m.set, m.way)
}
