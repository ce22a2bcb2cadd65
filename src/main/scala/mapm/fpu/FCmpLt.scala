package mapm.fpu

import chisel3._
import chisel3.util._
import mapm.model.FloatFormat

/** Pipelined floating-point comparison: out = a < b in format `fmt`, bit-exact with
  * [[mapm.model.SoftFloat.lt]]: false when either operand is a NaN; zeros of both signs, and
  * patterns with exponent field 0, are all equal to zero; infinities order as usual.
  *
  * One step (sign-magnitude compare) ended by a register when `stages` is 1. Latency: `stages`
  * cycles, 1 by default, 0 without the register. Throughput: one comparison per cycle.
  */
class FCmpLt(val fmt: FloatFormat, val stages: Int = 1) extends Module with PlannedPipeline {
  def weights: Seq[Double] = FCmpLt.weights
  override def desiredName: String = s"FCmpLt_${fmt.name}_s$stages"

  val io = IO(new Bundle {
    val in = Flipped(Valid(new FOperands(fmt)))
    val out = Valid(Bool())
  })

  val lt = FloatOrder.lt(fmt, io.in.bits.a, io.in.bits.b)
  private val p = new StepPipe(cuts, io.in.valid)
  io.out.bits := p.last(lt)
  io.out.valid := p.finish()
}

/** The order of bit patterns of `fmt` as [[mapm.model.SoftFloat.lt]] defines it: NaNs are
  * unordered, zeros of both signs and the patterns with exponent field 0 are all zero, infinities
  * order as usual. Combinational: a sign-magnitude comparison. */
object FloatOrder {
  /** Magnitude bits (exponent and fraction) with the zero patterns cleared. */
  private def magnitude(f: FloatFields, x: UInt): UInt = Mux(f.isZero(x), 0.U, f.magnitude(x))

  /** a < b (false when either is a NaN). */
  def lt(fmt: FloatFormat, a: UInt, b: UInt): Bool = {
    val f = FloatFields(fmt)
    val (sa, sb) = (f.sign(a), f.sign(b))
    val (ma, mb) = (magnitude(f, a), magnitude(f, b))
    val ordered = Mux(sa =/= sb, sa && (ma =/= 0.U || mb =/= 0.U), Mux(sa, ma > mb, ma < mb))
    ordered && !f.isNaN(a) && !f.isNaN(b)
  }

  /** a == b as values (false when either is a NaN; +0 == -0). */
  def eq(fmt: FloatFormat, a: UInt, b: UInt): Bool = {
    val f = FloatFields(fmt)
    val (ma, mb) = (magnitude(f, a), magnitude(f, b))
    ma === mb && (ma === 0.U || f.sign(a) === f.sign(b)) && !f.isNaN(a) && !f.isNaN(b)
  }
}

object FCmpLt {
  /** Estimated delay of its one step (docs/fpu.md). */
  val weights: Seq[Double] = Seq(1.5)
}
