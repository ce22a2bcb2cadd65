package mapm.uncore

import chisel3._
import chisel3.util._
import mapm.params.{MapmParams, SoGroup}
import mapm.util.{Index, RoundRobin, Rotate}

/** The ports of a Data bus, whichever [[mapm.params.SoBus]] builds it. */
class SoBusIO(p: MapmParams) extends Bundle {
  /** The TSMs' SO groups. */
  val in = Vec(p.counts.tsm, Flipped(Decoupled(new SoGroup(p))))
  /** Each SOM's lanes' free reservation-station entries. */
  val free = Input(Vec(p.counts.som, Vec(p.counts.soaPerSom, UInt(log2Ceil(p.rsPerSoa + 1).W))))
  /** The group each SOM takes this cycle. */
  val out = Output(Vec(p.counts.som, Valid(new SoGroup(p))))
}

/** The Data bus (3.2): hands the TSMs' SO groups to SOMs with room for them.
  *
  * Each cycle every SOM takes at most one group and every group goes to at most one SOM, whole.
  * A group fits a SOM when each of the SOM's lanes has free reservation-station entries for the
  * group's SOs of that lane. Groups are served in TSM order and each takes the first SOM that
  * fits and is still unclaimed, in SOM order; both orders start one place further every cycle
  * (the dissertation's rotating start index, which spreads the work over the SOMs, and the
  * same for the TSMs so that none is favoured). A group that fits no SOM waits in its TSM
  * (stall "RS full", 3.7).
  *
  * Latency: none (combinational). Throughput: min(TSMs, SOMs) groups per cycle.
  */
class DataBus(p: MapmParams) extends Module {
  private val t = p.counts.tsm
  private val s = p.counts.som
  private val a = p.counts.soaPerSom
  override def desiredName = s"DataBus_t${t}_s${s}_a$a"

  val io = IO(new SoBusIO(p))

  val startT = RegInit(0.U(Index.bits(t).W))
  val startS = RegInit(0.U(Index.bits(s).W))
  startT := Index.next(startT, t)
  startS := Index.next(startS, s)

  // fits(i): the SOMs group i fits, as an s-bit mask.
  private val fits = VecInit(io.in.map { g =>
    val need = SoGroup.needs(g.bits, a)
    VecInit(io.free.map(f => g.valid && need.zip(f).map { case (n, fr) => n <= fr }.reduce(_ && _))).asUInt
  })
  // Claims in rotated TSM order; claim(k) is the SOM (one-hot) taken by the k-th group in that order,
  // the group of TSM (startT + k) mod t.
  private val fitsInOrder = Rotate(fits, startT)
  private val afterS = RoundRobin.atOrAfter(startS, s)
  private var avail = ((BigInt(1) << s) - 1).U(s.W)
  private val claims = fitsInOrder.zipWithIndex.map { case (f, k) =>
    val oh = RoundRobin.firstOneHot(f & avail, afterS)
    if (k < t - 1) avail = avail & ~oh
    oh
  }
  // Back to TSM order: group i is the k-th with k = (i - startT) mod t.
  private val grant = Rotate(claims, startT, back = true)
  for (i <- 0 until t) io.in(i).ready := grant(i).orR
  private val flat = io.in.map(_.bits.asUInt) // each group's bits once, shared by every SOM's select
  for (j <- 0 until s) {
    val from = grant.map(_(j))
    io.out(j).valid := from.reduce(_ || _)
    io.out(j).bits := Mux1H(from, flat).asTypeOf(new SoGroup(p))
  }
}
