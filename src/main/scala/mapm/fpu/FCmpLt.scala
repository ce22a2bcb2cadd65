package mapm.fpu

import chisel3._
import chisel3.util._
import mapm.util.StageClocks
import mapm.numerics.FloatFormat

/** Pipelined floating-point comparison: out = a < b in format `fmt`, bit-exact with
  * [[mapm.numerics.SoftFloat.lt]]: false when either operand is a NaN; zeros of both signs, and
  * patterns with exponent field 0, are all equal to zero; infinities order as usual.
  *
  * One step (sign-magnitude compare) ended by a register when `stages` is 1. Latency: `stages`
  * cycles, 1 by default, 0 without the register. Throughput: one comparison per cycle. With
  * `gated` the register runs on `clocks(0)`, which the pipeline around gates ([[StepPipe]]).
  */
class FCmpLt(val fmt: FloatFormat, val stages: Int = 1, val gated: Boolean = false) extends Module with PlannedPipeline {
  def weights: Seq[Double] = FCmpLt.weights
  override def desiredName: String = s"FCmpLt_${fmt.name}_s$stages${StageClocks.suffix(gated)}"

  val io = IO(new Bundle {
    val in = Flipped(Valid(new FOperands(fmt)))
    val out = Valid(Bool())
    /** clocks(k): the clock of register stage k's data (stage-gated units only). */
    val clocks = StageClocks.port(stages, gated)
  })

  val lt = OrderParts(fmt, io.in.bits.a, io.in.bits.b).lt
  private val p = new StepPipe(cuts, io.in.valid, clocks = new StageClocks(io.clocks))
  io.out.bits := p.last(lt)
  io.out.valid := p.finish()
}

/** The order of two bit patterns of `fmt` as [[mapm.numerics.SoftFloat.lt]] defines it (NaNs are
  * unordered, zeros of both signs and the patterns with exponent field 0 are all zero,
  * infinities order as usual), split in two steps so that a register may sit between them: the
  * magnitudes' upper and lower halves are compared on their own ([[OrderParts.apply]]), then
  * combined with the signs ([[lt]], and [[eq]]: equal values, +0 = -0). */
class OrderParts(fmt: FloatFormat) extends Bundle {
  val hiLt = Bool()
  val hiEq = Bool()
  val loLt = Bool()
  val loEq = Bool()
  val signA = Bool()
  val signB = Bool()
  val zeroA = Bool()   // magnitude zero (exponent field 0)
  val zeroB = Bool()
  val nan = Bool()     // either is a NaN

  private def magLt: Bool = hiLt || (hiEq && loLt)
  private def magEq: Bool = hiEq && loEq
  private def magGt: Bool = !magLt && !magEq
  def lt: Bool = !nan && Mux(signA =/= signB, signA && !(zeroA && zeroB), Mux(signA, magGt, magLt))
  def eq: Bool = !nan && magEq && (zeroA || signA === signB)
}

object OrderParts {
  def apply(fmt: FloatFormat, a: UInt, b: UInt): OrderParts = {
    val f = FloatFields(fmt)
    def magnitude(x: UInt): UInt = Mux(f.isZero(x), 0.U, f.magnitude(x))
    val (ma, mb) = (magnitude(a), magnitude(b))
    val half = (fmt.width - 1) / 2
    val o = Wire(new OrderParts(fmt))
    o.hiLt := ma(fmt.width - 2, half) < mb(fmt.width - 2, half)
    o.hiEq := ma(fmt.width - 2, half) === mb(fmt.width - 2, half)
    o.loLt := ma(half - 1, 0) < mb(half - 1, 0)
    o.loEq := ma(half - 1, 0) === mb(half - 1, 0)
    o.signA := f.sign(a)
    o.signB := f.sign(b)
    o.zeroA := f.isZero(a)
    o.zeroB := f.isZero(b)
    o.nan := f.isNaN(a) || f.isNaN(b)
    o
  }
}

object FCmpLt {
  /** Estimated delay of its one step (docs/fpu.md). */
  val weights: Seq[Double] = Seq(1.5)
}
