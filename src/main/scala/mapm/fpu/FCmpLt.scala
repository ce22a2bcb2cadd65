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

  private val f = FloatFields(fmt)
  /** Magnitude bits (exponent and fraction) with the zero patterns cleared. */
  private def magnitude(x: UInt): UInt = Mux(f.isZero(x), 0.U, f.magnitude(x))

  val (a, b) = (io.in.bits.a, io.in.bits.b)
  val (sa, sb) = (f.sign(a), f.sign(b))
  val (ma, mb) = (magnitude(a), magnitude(b))
  val ordered = Mux(sa =/= sb, sa && (ma =/= 0.U || mb =/= 0.U), Mux(sa, ma > mb, ma < mb))
  val lt = ordered && !f.isNaN(a) && !f.isNaN(b)
  private val p = new StepPipe(cuts, io.in.valid)
  io.out.bits := p.last(lt)
  io.out.valid := p.finish()
}

object FCmpLt {
  /** Estimated delay of its one step (docs/fpu.md). */
  val weights: Seq[Double] = Seq(1.5)
}
