package mapm.tsearch

import chisel3._
import chisel3.util._
import mapm.fpu.{FAdd, FloatFields, OrderParts}
import mapm.numerics.FloatFormat

/** The conventional Tree Search Accelerator, the baseline of dissertation Figure 4.5: two
  * floating-point adders form p - h and -p - h (that is, -(p + h)), and two comparisons with s
  * and -s decide TC_L = (p - h < s) and TC_R = (p + h > s), that is -p - h < -s. Same ports and outcome as the online [[TSA]], and the same decisions:
  * exact ones, on the real values, for non-negative finite p, h, s in any [[FloatFormat]].
  *
  * '''Exactness.''' A rounded sum r = RN(p - h) can differ from the exact d = p - h, but never
  * across a value of the format: if r < s then d < s (else s, lying in [d, r), would be nearer d
  * than r is, or equal to d and then r = d exactly), and likewise if r > s then d > s. Only r = s
  * leaves the question open, and there d < s exactly when r lies above d: the adder reports
  * whether its result lies above the exact sum (`FAdd` with `direction`: rounded up in value, an
  * overflow to +infinity, a flush to zero of a negative sum). So, with r_R = RN(-p - h),
  * TC_L = r_L < s or (r_L = s and r_L above p - h), TC_R = r_R < -s or (r_R = -s and r_R above -p - h),
  * with no wider datapath ([[mapm.numerics.ConvTsaModel]] is the same rule in software; the tests check
  * it against exact decisions exhaustively at e3m3 and on the hard cases at fp32).
  *
  * An invalid operand (negative non-zero, infinite or NaN) sets `error` and both TC bits, as in
  * the TSA.
  *
  * Latency: [[ConvTSA.latency]] = add + 2 cycles: the adders' `addStages`, then the comparisons
  * in two registered steps (the magnitudes' halves compared, then combined with the signs and the
  * rounding's direction): 11 at fp32 with the default depth. Throughput: one operation per cycle. With
  * `stallable`, `en` freezes every register while low.
  */
class ConvTSA(fmt: FloatFormat, tagWidth: Int, stallable: Boolean = false, addStages: Int) extends TsaUnit {
  require(tagWidth >= 1, s"tag width must be at least 1, got $tagWidth")
  require(addStages >= 0, s"adder stages must be non-negative, got $addStages")
  override def desiredName = ConvTSA.name(fmt, tagWidth, stallable, addStages)

  val latency: Int = ConvTSA.latency(addStages)
  val io = IO(new TsaIO(fmt, tagWidth, stallable))
  private val enable = io.en.getOrElse(true.B)
  private val f = FloatFields(fmt)
  private val req = io.in.bits

  /** x with its sign flipped. */
  private def negate(x: UInt): UInt = Cat(!f.sign(x), f.magnitude(x))
  private def adder(a: UInt) = {
    val u = Module(new FAdd(fmt, addStages, stallable, direction = true))
    u.io.in.valid := io.in.valid
    u.io.in.bits.a := a
    u.io.in.bits.b := req.h
    u.io.in.bits.sub := true.B
    u.io.en.foreach(_ := enable)
    u
  }
  private val left = adder(req.p)          // p - h
  private val right = adder(negate(req.p)) // -p - h = -(p + h)

  private class Side extends Bundle {
    val s = UInt(fmt.width.W)
    val tag = UInt(tagWidth.W)
    val error = Bool()
  }
  private val side0 = Wire(new Side)
  side0.s := req.s
  side0.tag := req.tag
  side0.error := Seq(req.p, req.h, req.s).map(TsaUnit.invalid(f, _)).reduce(_ || _)
  private val side = ShiftRegister(side0, addStages, enable)

  // The comparisons in two steps: halves of the magnitudes, then r < t exactly for r the rounding of
  // a sum that lies `above` it or not: r < t, or r = t and r above the sum.
  private val partsL = RegEnable(OrderParts(fmt, left.io.out.bits, side.s), enable)
  private val partsR = RegEnable(OrderParts(fmt, right.io.out.bits, negate(side.s)), enable)
  private val aboveL = RegEnable(left.io.above.get, enable)
  private val aboveR = RegEnable(right.io.above.get, enable)
  private val side2 = RegEnable(side, enable)
  private val valid2 = RegEnable(left.io.out.valid && right.io.out.valid, false.B, enable)
  private val tcl = partsL.lt || (partsL.eq && aboveL)
  private val tcr = partsR.lt || (partsR.eq && aboveR)

  io.out.valid := RegEnable(valid2, false.B, enable)
  io.out.bits.tag := RegEnable(side2.tag, enable)
  io.out.bits.error := RegEnable(side2.error, enable)
  io.out.bits.tcl := RegEnable(tcl || side2.error, enable)
  io.out.bits.tcr := RegEnable(tcr || side2.error, enable)
}

object ConvTSA {
  /** The module name, e.g. `ConvTSA_e8m23_t16_a9` (`_en` when stallable). */
  def name(fmt: FloatFormat, tagWidth: Int, stallable: Boolean, addStages: Int): String =
    s"ConvTSA_${fmt.name}_t${tagWidth}_a$addStages${if (stallable) "_en" else ""}"

  /** Cycles from request to outcome: the adders, then the comparisons' two steps. */
  def latency(addStages: Int): Int = addStages + 2
}
