package mapm.shader

import chisel3._
import chisel3.experimental.hierarchy.{instantiable, public}
import chisel3.util._
import mapm.fpu.FpuDepth
import mapm.memory.{CacheConfig, CacheEvents, MemPort, ReadOnlyCache}
import mapm.params.{Fidelity, MapmParams, PhotonRecord, QueryData, Records, Rgb, SoGroup, SoResult}
import mapm.uncore.Shapes
import mapm.util.{ClockGate, Index, RoundRobin}

/** One shader operation waiting in a reservation station: its query and the photon's node index. */
class SoOp(p: MapmParams) extends Bundle {
  val query = new QueryData(p)
  val photon = UInt(p.indices.nodeBits.W)
}

/** One SOA's lane of a Shader Operation Module (3.5.1): a reservation station of
  * `rsPerSoa` entries, one bank of the SOM's SOP L1 and the [[SOA]].
  *
  * The SOM inserts up to three SOs per cycle (never more than `free`). Each waiting SO asks the SOP
  * L1 bank for its photon record (32 bytes: position, power r, g, b, kernel, BRDF;
  * docs/memory-layout.md), one request per cycle, the waiting entries served round-robin. When the
  * record arrives the SO issues into the SOA in that same cycle and its entry is free again (a
  * record with non-zero bits above a slot's format bits raises the sticky `error`): the
  * operands are then complete (Tomasulo-like, 3.5.1), so an SO never waits once its data is there
  * and the lane never stalls (3.7). The SOA's result leaves on `out` after its fixed latency with
  * the pixel, query and photon indices (carried through the SOA as its tag).
  *
  * Latency: insert, one cycle to the fetch request, the SOP L1 (3 cycles on a hit), then the SOA
  * ([[SOA.latency]]). Throughput: one SO per cycle.
  */
@instantiable
class SomLane(p: MapmParams) extends Module {
  private val fmt = p.numbers.format
  private val w = fmt.width
  private val records = p.records
  private val n = p.rsPerSoa
  val l1Config: CacheConfig = Shapes(p).sopL1
  override def desiredName = s"SomLane_${fmt.name}_g${p.numbers.guardDigits}_r$n"

  @public val io = IO(new Bundle {
    val h = Input(UInt(w.W))
    val photonBase = Input(UInt(p.memory.addressBits.W))
    val insert = Input(Vec(SoGroup.Size, Valid(new SoOp(p))))
    val free = Output(UInt(log2Ceil(n + 1).W))
    /** Results the consumer of `out` can still take (at most [[SomLane.resultFifo]]): the lane
      * takes new SOs only while those in its reservation station and its SOA fit in it. It may
      * fall only by the results the lane sends (the ring Data bus's credits rely on `free`
      * falling only by the SOs inserted). */
    val room = Input(UInt(log2Ceil(SomLane.resultFifo(p) + 1).W))
    val mem = new MemPort(l1Config.down)
    val out = Valid(new SoResult(p))
    /** An SO entered the SOA this cycle. */
    val issued = Output(Bool())
    val idle = Output(Bool())
    val l1 = Output(new CacheEvents)
    val error = Output(Bool())
  })

  val l1 = Module(new ReadOnlyCache(l1Config))
  io.mem <> l1.io.down
  io.l1 := l1.io.events
  val soa: ShaderUnit = {
    val (g, tags, depth) = (p.numbers.guardDigits, p.indices.pixelBits + p.indices.queryBits + p.indices.nodeBits, Some(FpuDepth.of(fmt, p.numbers.fpuStageWeight)))
    p.sim.fidelity match {
      case Fidelity.Full => Module(new SOA(fmt, g, tags, depth, p.numbers.arith, p.clocking.soaStageGate))
      case Fidelity.Timing => Module(new SoaTiming(fmt, g, tags, depth, p.numbers.arith, cond = p.sim.coproc))
    }
  }

  val valid = RegInit(VecInit(Seq.fill(n)(false.B)))
  val sent = RegInit(VecInit(Seq.fill(n)(false.B)))
  val ops = Reg(Vec(n, new SoOp(p)))
  private val rsFree = PopCount(valid.map(!_))

  // Insertion into the lowest free entries, in group order.
  private var avail = ~valid.asUInt
  for (k <- 0 until SoGroup.Size) {
    val at = PriorityEncoderOH(avail)
    for (e <- 0 until n) when(io.insert(k).valid && at(e)) { valid(e) := true.B; sent(e) := false.B; ops(e) := io.insert(k).bits }
    if (k < SoGroup.Size - 1) avail = Mux(io.insert(k).valid, avail & ~at, avail)
  }

  // Photon-record requests, round-robin over the entries still to ask.
  val rrNext = RegInit(0.U(Index.bits(n).W))
  private val (want, pick) = RoundRobin.first(valid.asUInt & ~sent.asUInt, rrNext)
  l1.io.up.req.valid := want
  l1.io.up.req.bits.addr := io.photonBase + (ops(pick).photon << Records.indexShift(records.photon))
  l1.io.up.req.bits.id := pick
  l1.io.up.req.bits.len := 0.U
  when(l1.io.up.req.fire) { sent(pick) := true.B; rrNext := Index.next(pick, n) }

  // A record arrives: the SO issues.
  l1.io.up.resp.ready := true.B
  private val r = l1.io.up.resp
  private val op = ops(r.bits.id)
  private val photon = r.bits.data.asTypeOf(new PhotonRecord(records.slot, w))
  when(r.fire) { valid(r.bits.id) := false.B }
  soa.io.in.valid := r.fire
  soa.io.in.bits.px := photon.x.value
  soa.io.in.bits.py := photon.y.value
  soa.io.in.bits.pz := photon.z.value
  for (c <- 0 until Rgb.Channels) {
    soa.io.in.bits.power(c) := photon.power(c).value
    soa.io.in.bits.contrib(c) := op.query.contrib(c)
  }
  soa.io.in.bits.kernel := photon.kernel.value
  soa.io.in.bits.brdf := photon.brdf.value
  soa.io.in.bits.h := io.h
  soa.io.in.bits.qx := op.query.x
  soa.io.in.bits.qy := op.query.y
  soa.io.in.bits.qz := op.query.z
  soa.io.in.bits.tag := Cat(op.query.pixel, op.query.q, op.photon)
  io.issued := r.fire
  // A photon record's slots hold format bits zero-extended: anything above them is a malformed image.
  private val malformed = RegInit(false.B)
  if (w < 8 * records.slot) when(r.fire && photon.slots.map(_.pad.orR).reduce(_ || _)) { malformed := true.B }
  io.error := l1.io.protocolError || malformed

  io.out.valid := soa.io.out.valid
  io.out.bits.colour := soa.io.out.bits.colour
  io.out.bits.flags := soa.io.out.bits.flags
  io.out.bits.cond := soa.io.out.bits.cond
  private val nb = p.indices.nodeBits
  private val qb = p.indices.queryBits
  io.out.bits.pixel := soa.io.out.bits.tag >> (nb + qb)
  io.out.bits.q := soa.io.out.bits.tag(nb + qb - 1, nb)
  io.out.bits.photon := soa.io.out.bits.tag(nb - 1, 0)

  // SOs inside the SOA's pipeline.
  val inSoa = RegInit(0.U(log2Ceil(soa.latency + 2).W))
  inSoa := inSoa + soa.io.in.valid.asUInt - soa.io.out.valid.asUInt
  // Room for new SOs: the consumer's room less the SOs that will still leave on `out`.
  private val pending = (n.U - rsFree) +& inSoa
  private val spare = Mux(io.room > pending, io.room - pending, 0.U)
  io.free := Mux(spare < rsFree, spare, rsFree)
  io.idle := !valid.asUInt.orR && inSoa === 0.U
  // The SOA is a pipeline without feedback: each stage's registers hold the operation that entered
  // so many cycles earlier, and nothing else. While no operation is inside it or entering it, its
  // clock stops (a gated stage holds values no valid bit points to); it runs in reset, so that
  // its valid bits clear.
  if (p.clocking.soaClockGate) soa.clock := ClockGate(clock, reset.asBool || soa.io.in.valid || inSoa =/= 0.U)
}

object SomLane {
  /** Results a lane may have on their way at once (`CoprocParams.laneFifo`, or where it is 0 its
    * reservation-station entries and its SOA's latency, which a running lane fills, plus 32 that
    * absorb a consumer's bursts). A consumer that always has this much room never slows the lane. */
  def resultFifo(p: MapmParams): Int =
    if (p.coproc.laneFifo != 0) p.coproc.laneFifo
    else p.rsPerSoa + SOA.latency(p.numbers.format, p.numbers.guardDigits, FpuDepth.of(p.numbers.format, p.numbers.fpuStageWeight), p.numbers.arith) + 32
}

