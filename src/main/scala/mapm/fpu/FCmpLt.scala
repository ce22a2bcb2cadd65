package mapm.fpu

import chisel3._
import chisel3.util._
import mapm.model.FloatFormat

/** Pipelined floating-point comparison: out = a < b in format `fmt`, bit-exact with
  * [[mapm.model.SoftFloat.lt]]: false when either operand is a NaN; zeros of both signs, and
  * patterns with exponent field 0, are all equal to zero; infinities order as usual.
  *
  * One stage (sign-magnitude compare) ended by an optional register. Latency: 1 by default
  * ([[FCmpLt.stages]]); 0 with the register left out. Throughput: one comparison per cycle.
  */
class FCmpLt(val fmt: FloatFormat, val cuts: Seq[Boolean] = FCmpLt.defaultCuts) extends Module with PipelineCuts {
  require(cuts.length == FCmpLt.stages, s"FCmpLt has ${FCmpLt.stages} cut point, got ${cuts.length}")
  override def desiredName: String = nameWithCuts(s"FCmpLt_${fmt.name}")

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
  io.out.valid := validAt(0, io.in.valid)
  io.out.bits := dataAt(0, io.in.valid, lt)
}

object FCmpLt {
  val stages = 1
  val defaultCuts: Seq[Boolean] = Seq.fill(stages)(true)
}
