package mapm.shader

import chisel3._
import chisel3.util._
import mapm.params.{MapmParams, SoGroup}
import mapm.util.Pick

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

  val io = IO(new Bundle {
    val in = Vec(t, Flipped(Decoupled(new SoGroup(p))))
    val free = Input(Vec(s, Vec(a, UInt(log2Ceil(p.rsPerSoa + 1).W))))
    val out = Output(Vec(s, Valid(new SoGroup(p))))
  })

  val startT = RegInit(0.U(Pick.bits(t).W))
  val startS = RegInit(0.U(Pick.bits(s).W))
  startT := Pick.next(startT, t)
  startS := Pick.next(startS, s)

  // fits(i): the SOMs group i fits, as an s-bit mask.
  private val fits = VecInit(io.in.map { g =>
    val need = Som.needs(g.bits, a)
    VecInit(io.free.map(f => g.valid && need.zip(f).map { case (n, fr) => n <= fr }.reduce(_ && _))).asUInt
  })
  /** (start + k) mod n for a constant k < n; for a power-of-two n the low bits of the sum (no
    * compare, no mixed-width select for lint to flag). */
  private def rot(start: UInt, k: Int, n: Int): UInt =
    if (n == 1) 0.U
    else if (isPow2(n)) (start +% k.U(start.getWidth.W))(Pick.bits(n) - 1, 0)
    else { val x = start +& k.U; Mux(x >= n.U, x - n.U, x)(Pick.bits(n) - 1, 0) }

  // Claims in rotated TSM order; claim(k) is the SOM (one-hot) taken by the k-th group in that order.
  private var avail = ((BigInt(1) << s) - 1).U(s.W)
  private val claims = (0 until t).map { k =>
    val oh = Pick.roundRobinOH(fits(rot(startT, k, t)) & avail, startS)
    if (k < t - 1) avail = avail & ~oh
    oh
  }
  private val claimOf = VecInit(claims)
  // Back to TSM order: group i is the k-th with k = (i - startT) mod t.
  private val grant = (0 until t).map(i => if (t == 1) claimOf(0) else claimOf(rot(t.U - startT, i, t)))
  for (i <- 0 until t) io.in(i).ready := grant(i).orR
  for (j <- 0 until s) {
    val from = grant.map(_(j))
    io.out(j).valid := from.reduce(_ || _)
    io.out(j).bits := Mux1H(from, io.in.map(_.bits))
  }
}
