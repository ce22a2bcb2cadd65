package mapm.uncore

import chisel3._
import chisel3.util._
import mapm.params.{MapmParams, SoGroup}
import mapm.memory.RegFifo
import mapm.util.{Boundary, Index, Rotate}

/** A group waiting at the ring bus's input, with its SOs per SOM lane (computed once, on the way in). */
class RingEntry(p: MapmParams) extends Bundle {
  val group = new SoGroup(p)
  val need = Vec(p.counts.soaPerSom, UInt(RingBus.needBits.W))
}

/** The staged Data bus (docs/mapm.md, "The ring bus"): hands the TSMs' SO groups to SOMs with room
  * for them through a ring of credit tokens and a registered rotation.
  *
  * Slots 0 .. N-1 (N = max(TSMs, SOMs)) sit on a ring; TSM i is at slot i. Each SOM owns one token,
  * its lanes' credits, and every cycle every token moves one slot down (slot k to k - 1 mod N), so
  * that slot k holds SOM (k + r) mod N's token while the rotation counter `r` stands at r. TSM i
  * takes the token at slot i, or, when TSM i + 1 does not, the one at slot i + 1, if its waiting
  * group's SOs per lane fit the token's credits; it takes them off and the group reaches its SOM
  * through a barrel rotation by r, registered after every [[RingBus.LevelsPerStage]] select levels
  * and at its end. What each SOM lane's free count grew by besides the group the SOM took (entries
  * it issued, or the consumer's room) returns to its token through a rotation of the same kind. A
  * lane's free count falls only by the groups it takes, so a token's credits plus its groups in
  * flight never exceed its lanes' free entries: a SOM takes every group that reaches it.
  *
  * Fairness: a TSM whose group no token took for N cycles reserves its own token when nobody
  * holds it; no other TSM takes from that token, and the TSM from no other, until the group fits.
  * With TSMs <= SOMs a group waits at most 3N + F + 2 [[latency]] + 4 cycles at the head of its
  * queue, F the time the reserved SOM takes to free what the group needs (docs/mapm.md).
  *
  * Latency: a group's input queue (one cycle), then [[latency]] cycles from its grant to its SOM;
  * a lane's freed entry is back in its token [[returnLatency]] + 2 cycles later. Throughput: one
  * group a cycle per TSM and per SOM. Logic: N log N two-way selects of a group, N tokens of
  * a x log2(RS + 1) bits; no path through more than four select levels, and none from a SOM lane
  * to a TSM in one cycle (the queue's ready and head are registers).
  */
class RingBus(p: MapmParams) extends Module {
  private val t = p.counts.tsm
  private val s = p.counts.som
  private val a = p.counts.soaPerSom
  private val n = p.rsPerSoa
  private val slots = t max s
  private val w = log2Ceil(n + 1)
  override def desiredName = s"RingBus_t${t}_s${s}_a${a}_r$n"
  Boundary.registered(this)

  val io = IO(new SoBusIO(p))

  /** Registers from a grant to its SOM. */
  val latency: Int = RingBus.stages(slots, RingBus.LevelsPerStage)

  // Each TSM's groups wait in a two-entry queue: its ready and its head are registers.
  private val heads = io.in.map { in =>
    val q = Module(new RegFifo(new RingEntry(p), 2))
    q.io.enq.valid := in.valid
    q.io.enq.bits.group := in.bits
    q.io.enq.bits.need := VecInit(SoGroup.needs(in.bits, a))
    in.ready := q.io.enq.ready
    q.io.deq
  }

  private val r = RegInit(0.U(Index.bits(slots).W))
  r := Index.next(r, slots)

  // A rotation of `v` by `by` with a register after every `perStage` levels and, if
  // `registerLast`, after the last.
  private def pipelined[T <: Data](v: Seq[T], by: UInt, back: Boolean, perStage: Int, registerLast: Boolean)(reg: T => T): Seq[T] = {
    val stages = RingBus.groupsOfLevels(slots, perStage)
    // The amount's bits that later stages still use travel with the data, one register a stage.
    val (out, _) = stages.zipWithIndex.foldLeft((v, stages.flatten.map(b => b -> by(b)).toMap)) { case ((cur, amt), (levels, i)) =>
      val rotated0 = levels.foldLeft(cur)((c, b) => Rotate.level(c, amt(b), b, back))
      val rotated = if (i < stages.size - 1 || registerLast) rotated0.map(reg) else rotated0
      (rotated, stages.drop(i + 1).flatten.map(b => b -> RegNext(amt(b))).toMap)
    }
    out
  }

  // Returned credits: the lanes' free counts enter through a register (no path from a SOM lane's
  // state into the ring in one cycle), and `took` is delayed with them. acc = those free counts
  // less what the SOM took, one cycle late, so free - acc is what each lane's free count grew by
  // besides the group the SOM took: every credit comes back one cycle after the unregistered
  // count would have brought it.
  private val zeroLanes = VecInit(Seq.fill(s)(VecInit(Seq.fill(a)(0.U(w.W)))))
  private val took = Wire(Vec(s, Vec(a, UInt(w.W))))
  private val free = RegNext(io.free, zeroLanes)
  private val tookThen = RegNext(took, zeroLanes)
  private val acc = RegNext(VecInit(free.zip(tookThen).map { case (f, k) => VecInit(f.zip(k).map { case (x, y) => x - y }) }), zeroLanes)
  private val grew = free.zip(acc).map { case (f, k) => VecInit(f.zip(k).map { case (x, y) => x - y }) }
  for ((f, k) <- free.zip(acc); (x, y) <- f.zip(k))
    assert(x >= y, "ring Data bus: a SOM lane's free count fell by more than the SOs it took")
  // Credits are narrow: their rotation takes ReturnLevelsPerStage levels a stage, the last one
  // straight into the tokens. The token that slot k holds `returnLatency` cycles from now is SOM
  // (k + r + returnLatency) mod slots's.
  val returnLatency: Int = RingBus.stages(slots, RingBus.ReturnLevelsPerStage) - 1
  private val rRet = RegInit((returnLatency % slots).U(Index.bits(slots).W))
  rRet := Index.next(rRet, slots)
  private val back = pipelined(grew ++ Seq.fill(slots - s)(VecInit(Seq.fill(a)(0.U(w.W)))), rRet, back = false, RingBus.ReturnLevelsPerStage, registerLast = false)(
    x => RegNext(x, VecInit(Seq.fill(a)(0.U(w.W)))))

  // The tokens, their reservations and each TSM's wait.
  private val noResv = 0.U.asTypeOf(Valid(UInt(Index.bits(t).W)))
  private val credit = RegInit(VecInit(Seq.fill(slots)(VecInit(Seq.fill(a)(0.U(w.W))))))
  private val real = RegInit(VecInit(Seq.tabulate(slots)(k => (k < s).B)))
  private val resv = RegInit(VecInit(Seq.fill(slots)(noResv)))
  private val holds = RegInit(VecInit(Seq.fill(t)(false.B)))
  private val waited = RegInit(VecInit(Seq.fill(t)(0.U(log2Ceil(slots + 1).W))))

  // TSM i may take the token at slot i (its own) or, when TSM i + 1 does not take it, the one at
  // slot i + 1 (its next): whether TSM i's group may take the token at slot k.
  private def mayTake(i: Int, k: Int): Bool = {
    val h = heads(i)
    val mine = resv(k).valid && resv(k).bits === i.U
    val fits = h.bits.need.zip(credit(k)).map { case (x, c) => x <= c }.reduce(_ && _)
    h.valid && real(k) && fits && (!resv(k).valid || mine) && (!holds(i) || mine)
  }
  private val own = Seq.tabulate(slots)(k => if (k < t) mayTake(k, k) else false.B)
  private val next = Seq.tabulate(slots) { i =>
    val k = (i + 1) % slots
    if (i < t && slots > 1) !own(i) && !own(k) && mayTake(i, k) else false.B
  }
  private def prev(k: Int) = (k + slots - 1) % slots

  private val offers = Wire(Vec(slots, Valid(new RingEntry(p))))
  for (k <- 0 until slots) {
    val down = prev(k)
    // The token at slot k goes to TSM k (own) or TSM k - 1 (its next), or to nobody.
    val byNext = if (down < t && slots > 1) next(down) else false.B
    offers(k).valid := own(k) || byNext
    offers(k).bits := (if (k < t && down < t && slots > 1) Mux(own(k), heads(k).bits, heads(down).bits)
      else if (k < t) heads(k).bits else if (down < t) heads(down).bits else 0.U.asTypeOf(new RingEntry(p)))
    val take = Mux(offers(k).valid, offers(k).bits.need, VecInit(Seq.fill(a)(0.U(RingBus.needBits.W))))
    credit(down) := VecInit(credit(k).zip(back(k)).zip(take).map { case ((c, g), x) => c + g - x })
    real(down) := real(k)
    // A reservation ends when its holder takes the token; a TSM that has waited a whole round
    // reserves its own token when nobody holds it.
    val taker = Mux(own(k), k.U, down.U)
    resv(down) := resv(k)
    when(offers(k).valid && resv(k).valid && resv(k).bits === taker) { resv(down) := noResv }
    if (k < t) {
      val h = heads(k)
      val granted = own(k) || next(k)
      val starving = waited(k) === slots.U
      val reserve = h.valid && !granted && starving && !holds(k) && real(k) && !resv(k).valid
      h.ready := granted
      when(reserve) { resv(down).valid := true.B; resv(down).bits := k.U }
      holds(k) := Mux(reserve, true.B, Mux(granted, false.B, holds(k)))
      waited(k) := Mux(!h.valid || granted, 0.U, Mux(starving, waited(k), waited(k) + 1.U))
    }
  }

  // Granted groups to their SOMs: slot k's group goes to SOM (k + r) mod slots.
  private val arrive = pipelined(offers, r, back = true, RingBus.LevelsPerStage, registerLast = true) { x =>
    val y = Wire(Valid(new RingEntry(p)))
    y.valid := RegNext(x.valid, false.B)
    y.bits := RegNext(x.bits)
    y
  }
  for (j <- 0 until s) {
    io.out(j).valid := arrive(j).valid
    io.out(j).bits := arrive(j).bits.group
    took(j) := VecInit(arrive(j).bits.need.map(x => Mux(arrive(j).valid, x, 0.U)))
  }
}

object RingBus {
  /** Bits of a group's SOs for one lane (at most [[SoGroup.Size]]). */
  val needBits: Int = log2Ceil(SoGroup.Size + 1)

  /** Select levels between two registers of the groups' rotation: four, so that up to 16 slots
    * take one cycle from grant to SOM. */
  val LevelsPerStage = 4

  /** Select levels between two registers of the credits' rotation (a few bits a slot). */
  val ReturnLevelsPerStage = 4

  /** A rotation's levels for `slots` slots, `perStage` to a register stage (one stage with no level
    * for one slot). */
  def groupsOfLevels(slots: Int, perStage: Int): Seq[Seq[Int]] = {
    val g = Rotate.levels(slots).grouped(perStage).toSeq
    if (g.isEmpty) Seq(Seq.empty) else g
  }

  /** Registers of a rotation of `slots` slots, `perStage` levels to a stage. */
  def stages(slots: Int, perStage: Int): Int = groupsOfLevels(slots, perStage).size
}
