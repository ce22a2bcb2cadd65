package mapm.util

import chisel3._

/** Per-stage clock gating of a fixed-latency pipeline whose registers each hold one operation's
  * state (every register of the SOA's colour chains and cond check: no stall, no feedback between
  * operations).
  *
  * Depth d counts the cycles of an operation: it is at depth 0 in the cycle it is on the
  * pipeline's input, at depth d d cycles later. A register that takes the operation's state at
  * the end of its depth-d cycle needs a clock edge then only if an operation is at depth d:
  * [[clock]](d) is the clock gated by the valid bit of depth d ([[ClockGate]]: `en` seen in a
  * cycle decides that cycle's edge). The valid bits travel in a plain register chain on the
  * ungated clock, and the gates are shared by every register of their depth, across the units
  * that take their [[StageClocks]] from here ([[connect]]).
  *
  * With `gated` false every depth's clock is the module's clock: no gate, no extra register, the
  * same hardware as a pipeline without gating. Gated or not, an operation's registers load in
  * the same cycles with the same values; a gated register only keeps its old value, instead of
  * loading a value no operation carries, in the cycles without an operation at its depth. So the
  * valid results, their cycles and every counter are the same.
  *
  * Build it inside the module whose clock it gates, with the valid bit of depth 0.
  */
final class StageGates(valid0: Bool, val gated: Boolean) {
  private val validAt = scala.collection.mutable.ArrayBuffer[Bool](valid0)
  private val clocks = scala.collection.mutable.HashMap.empty[Int, Clock]
  private val base: Clock = Module.clock

  /** The valid bit of depth `d` (the operation that entered `d` cycles ago), on the ungated clock. */
  def valid(d: Int): Bool = {
    require(d >= 0, s"pipeline depth $d is negative")
    while (validAt.size <= d) validAt += withClock(base)(RegNext(validAt.last, false.B))
    validAt(d)
  }

  /** The clock of the registers that take an operation's state at the end of its depth-`d` cycle. */
  def clock(d: Int): Clock = if (!gated) base else clocks.getOrElseUpdate(d, ClockGate(base, valid(d)))

  /** `x` registered at the end of depth `d`: the operation's value one depth later. */
  def reg[T <: Data](x: T, d: Int): T = withClock(clock(d))(StageGates.register(x))

  /** `x` delayed by `n` registers, the first taking it at the end of depth `d`. */
  def shift[T <: Data](x: T, n: Int, d: Int): T = (0 until n).foldLeft(x)((v, k) => reg(v, d + k))

  /** `x`, taken at the end of depth `d`, `n` cycles later: gated, a [[DelayRing]] (each operation
    * clocks one row instead of `n` stages) when that costs fewer clocked flip-flops per operation
    * than the shift register ([[StageGates.ringPays]]); else [[shift]]. */
  def delay[T <: Data](x: T, n: Int, d: Int): T =
    if (gated && StageGates.ringPays(x.getWidth, n)) DelayRing(x, valid(d), valid(d + n - 1), n) else shift(x, n, d)

  /** Drives a unit's stage clocks (when it has them): its local depth k is depth `offset` + k here. */
  def connect(unit: Option[Vec[Clock]], offset: Int): Unit =
    unit.foreach(c => c.zipWithIndex.foreach { case (port, k) => port := clock(offset + k) })
}

object StageGates {
  /** Whether a [[DelayRing]] of `depth` cycles for `width` bits clocks fewer flip-flops per
    * operation than a `depth`-stage shift register: 2 width (a row and the output register) +
    * 2 depth (each gate's latch, clocked every cycle, at about one operation per two cycles)
    * against width x depth. */
  def ringPays(width: Int, depth: Int): Boolean = depth >= 3 && 2 * width + 2 * depth < width * depth

  /** A register that keeps the exact type and width of its input (`mapm.arith.StageReg` is this). */
  def register[T <: Data](x: T): T = {
    val r = Reg(chiselTypeOf(x))
    r := x
    r
  }
}

/** The stage clocks a pipelined unit takes from its parent's [[StageGates]]: `count` clocks,
  * local depth k's being the clock of the registers that take an operation's state at the end of
  * the unit's k-th cycle (its own definition of depth 0, stated with its timing). Without
  * `gated` the unit has no such port and every register uses the module clock.
  */
final class StageClocks(val port: Option[Vec[Clock]]) {
  /** Elaborates `body` (its registers) on local depth `k`'s clock. */
  def at[T](k: Int)(body: => T): T = port match {
    case Some(c) =>
      require(k >= 0 && k < c.size, s"stage clock $k of ${c.size}")
      withClock(c(k))(body)
    case None => body
  }

  /** `x` registered at the end of local depth `k`. */
  def reg[T <: Data](x: T, k: Int): T = at(k)(StageGates.register(x))

  /** `x` delayed by `n` registers from local depth `k` on. */
  def shift[T <: Data](x: T, n: Int, k: Int): T = (0 until n).foldLeft(x)((v, i) => reg(v, k + i))
}

object StageClocks {
  /** The input port of `count` stage clocks, when `gated` (call it inside `IO(new Bundle { ... })`). */
  def port(count: Int, gated: Boolean): Option[Vec[Clock]] = if (gated) Some(Input(Vec(count, Clock()))) else None

  /** Name suffix of a unit with stage clocks. */
  def suffix(gated: Boolean): String = if (gated) "_sg" else ""
}
