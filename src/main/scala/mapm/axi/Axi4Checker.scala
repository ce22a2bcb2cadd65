package mapm.axi

import chisel3._
import chisel3.util._
import mapm.memory.RegFifo

/** Watches one AXI4 port and flags every rule either side breaks (docs/coprocessor.md, "AXI4
  * rules"). It only observes: every signal of the port is an input.
  *
  * The master's rules ([[Axi4Checker.MasterRules]]): AR, AW and W keep valid and their payload
  * until the handshake; a burst is INCR, no wider than the bus, and stays inside one 4 KiB page;
  * W beats belong to an accepted AW, in order, with WLAST on the burst's last beat and only there;
  * a read id is not reused while a read with it is outstanding (the MAPM's ids are unique, so R
  * beats name their burst). The memory's rules ([[Axi4Checker.SlaveRules]]): R and B keep valid and
  * their payload until the handshake; an R beat answers an outstanding read, with RLAST on its
  * last beat and only there; a B answers a write whose data has all been sent.
  *
  * The fault outputs are sticky, one bit per rule. `idle` is high while nothing is outstanding:
  * no read burst, no AW waiting for its data, no write waiting for its B.
  *
  * Latency: a fault shows the cycle after the handshake or the cycle that broke the rule.
  * Throughput: one beat on every channel each cycle.
  *
  * @param maxReads  read bursts outstanding that it can follow (more is a fault)
  * @param maxWrites AWs whose data has not all been sent, and writes awaiting their B, that it can
  *                  follow (more is a fault)
  */
class Axi4Checker(p: Axi4Params, maxReads: Int = 64, maxWrites: Int = 8) extends Module {
  require(maxReads >= 1 && maxWrites >= 1, s"the AXI4 checker follows at least one read and one write, got $maxReads and $maxWrites")
  override def desiredName = s"Axi4Checker_id${p.idBits}_r${maxReads}_w$maxWrites"
  import Axi4Checker._

  val io = IO(new Bundle {
    val axi = Input(new Axi4(p))
    val masterFault = Output(UInt(MasterRules.size.W))
    val slaveFault = Output(UInt(SlaveRules.size.W))
    val idle = Output(Bool())
  })
  private val a = io.axi
  private val ids = 1 << p.idBits

  /** Whether a channel dropped valid or changed its payload before its handshake. */
  private def unstable[T <: Data](c: DecoupledIO[T]): Bool = {
    val held = RegNext(c.valid && !c.ready, false.B)
    val bits = RegNext(c.bits)
    held && (!c.valid || c.bits.asUInt =/= bits.asUInt)
  }
  /** Whether a burst is not INCR, wider than the bus or crosses a 4 KiB boundary. */
  private def badBurst(x: Axi4Addr): Bool = {
    val bytes = (x.len +& 1.U) << x.size
    x.burst =/= Axi4.BurstIncr || x.size > p.sizeCode.U || (x.addr(11, 0) +& bytes) > Axi4.BoundaryBytes.U
  }

  // Reads: a table of the bursts outstanding (one per id), each with its beats left.
  private val rValid = RegInit(VecInit(Seq.fill(maxReads)(false.B)))
  private val rId = Reg(Vec(maxReads, UInt(p.idBits.W)))
  private val rLeft = Reg(Vec(maxReads, UInt(8.W)))
  private val rFire = a.r.fire
  private val rHit = VecInit((0 until maxReads).map(i => rValid(i) && rId(i) === a.r.bits.id))
  private val rKnown = rHit.asUInt.orR
  private val rAt = PriorityEncoder(rHit)
  private val rLastDue = rLeft(rAt) === 0.U
  private val rEnds = rFire && rKnown && rLastDue
  when(rFire && rKnown) { rLeft(rAt) := rLeft(rAt) - 1.U }
  when(rEnds) { rValid(rAt) := false.B }
  private val arHit = VecInit((0 until maxReads).map(i => rValid(i) && rId(i) === a.ar.bits.id && !(rEnds && rAt === i.U)))
  private val arReuse = a.ar.fire && arHit.asUInt.orR
  private val rFree = VecInit(rValid.map(!_))
  private val arFull = a.ar.fire && !rFree.asUInt.orR
  private val rSlot = PriorityEncoder(rFree)
  when(a.ar.fire && !arFull) {
    rValid(rSlot) := true.B
    rId(rSlot) := a.ar.bits.id
    rLeft(rSlot) := a.ar.bits.len
  }

  // Writes: the AWs whose data is being sent, in order; then a table of the bursts sent awaiting B.
  private val awQ = Module(new RegFifo(new Axi4Checker.Burst(p), maxWrites))
  awQ.io.enq.valid := a.aw.fire
  awQ.io.enq.bits.id := a.aw.bits.id
  awQ.io.enq.bits.len := a.aw.bits.len
  private val beat = RegInit(0.U(8.W))
  private val wFire = a.w.fire
  private val wOwned = awQ.io.deq.valid
  private val wLastDue = beat === awQ.io.deq.bits.len
  private val wEnds = wFire && wOwned && wLastDue
  awQ.io.deq.ready := wEnds
  when(wFire && wOwned) { beat := Mux(wLastDue, 0.U, beat + 1.U) }
  private val bValid = RegInit(VecInit(Seq.fill(maxWrites)(false.B)))
  private val bId = Reg(Vec(maxWrites, UInt(p.idBits.W)))
  private val bHit = VecInit((0 until maxWrites).map(i => bValid(i) && bId(i) === a.b.bits.id))
  private val bKnown = bHit.asUInt.orR
  when(a.b.fire && bKnown) { bValid(PriorityEncoder(bHit)) := false.B }
  private val bFree = VecInit(bValid.map(!_))
  private val sentFull = wEnds && !bFree.asUInt.orR
  when(wEnds && !sentFull) {
    bValid(PriorityEncoder(bFree)) := true.B
    bId(PriorityEncoder(bFree)) := awQ.io.deq.bits.id
  }

  private val master = Wire(Vec(MasterRules.size, Bool()))
  master(0) := unstable(a.ar)
  master(1) := unstable(a.aw)
  master(2) := unstable(a.w)
  master(3) := a.ar.valid && badBurst(a.ar.bits)
  master(4) := a.aw.valid && badBurst(a.aw.bits)
  master(5) := wFire && (!wOwned || a.w.bits.last =/= wLastDue)
  master(6) := arReuse
  master(7) := (a.aw.fire && !awQ.io.enq.ready) || arFull || sentFull

  private val slave = Wire(Vec(SlaveRules.size, Bool()))
  slave(0) := rFire && !rKnown
  slave(1) := rFire && rKnown && a.r.bits.last =/= rLastDue
  slave(2) := unstable(a.r)
  slave(3) := a.b.fire && !bKnown
  slave(4) := unstable(a.b)

  private val mSticky = RegInit(0.U(MasterRules.size.W))
  private val sSticky = RegInit(0.U(SlaveRules.size.W))
  mSticky := mSticky | master.asUInt
  sSticky := sSticky | slave.asUInt
  io.masterFault := mSticky
  io.slaveFault := sSticky
  io.idle := !rValid.asUInt.orR && !awQ.io.deq.valid && !bValid.asUInt.orR
}

object Axi4Checker {
  /** A write burst whose data is being sent. */
  class Burst(p: Axi4Params) extends Bundle {
    val id = UInt(p.idBits.W)
    val len = UInt(8.W)
  }

  /** The master's rules, bit by bit of `masterFault`. */
  val MasterRules: Seq[String] = Seq(
    "ARVALID dropped or the AR payload changed before ARREADY",
    "AWVALID dropped or the AW payload changed before AWREADY",
    "WVALID dropped or the W payload changed before WREADY",
    "an AR burst is not INCR, is wider than the bus or crosses a 4 KiB boundary",
    "an AW burst is not INCR, is wider than the bus or crosses a 4 KiB boundary",
    "a W beat with no accepted AW, or WLAST not on the burst's last beat",
    "a read id reused while a read with it is outstanding",
    "more reads or writes outstanding than the checker follows")
  /** The memory's rules, bit by bit of `slaveFault`. */
  val SlaveRules: Seq[String] = Seq(
    "an R beat for an id with no read outstanding",
    "RLAST not on the burst's last beat",
    "RVALID dropped or the R payload changed before RREADY",
    "a B for an id with no write whose data was all sent",
    "BVALID dropped or the B payload changed before BREADY")
}
