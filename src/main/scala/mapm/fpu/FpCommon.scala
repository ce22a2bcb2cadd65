package mapm.fpu

import chisel3._
import chisel3.util._
import mapm.model.FloatFormat

/** Two operand bit patterns of format `fmt`. */
class FOperands(fmt: FloatFormat) extends Bundle {
  val a = UInt(fmt.width.W)
  val b = UInt(fmt.width.W)
}

/** An operand's fields as the arithmetic units read them (project conventions, docs/fpu.md):
  * exponent field 0 is a zero whatever the mantissa (`sig` = 0, `exp` = 0), all-ones exponent is
  * infinity or NaN. `sig` carries the hidden bit: manWidth+1 bits. */
class FUnpacked(fmt: FloatFormat) extends Bundle {
  val sign = Bool()
  val exp = UInt(fmt.expWidth.W)
  val sig = UInt((fmt.manWidth + 1).W)
  val isZero = Bool()
  val isInf = Bool()
  val isNaN = Bool()
}

/** The fields of a bit pattern of format `fmt`, read the one way every unit reads them (project
  * conventions, docs/fpu.md): exponent field 0 is a zero whatever the fraction, all-ones exponent
  * is infinity (fraction 0) or NaN. Combinational: slices and a few gates, no state. */
final class FloatFields(fmt: FloatFormat) {
  def sign(x: UInt): Bool = x(fmt.width - 1)
  /** The biased exponent field. */
  def exp(x: UInt): UInt = x(fmt.width - 2, fmt.manWidth)
  /** The fraction field (the mantissa without the hidden bit). */
  def frac(x: UInt): UInt = x(fmt.manWidth - 1, 0)
  /** Exponent and fraction: the value's magnitude as an unsigned pattern. */
  def magnitude(x: UInt): UInt = x(fmt.width - 2, 0)
  /** The value is zero: exponent field 0. */
  def isZero(x: UInt): Bool = exp(x) === 0.U
  /** A zero whose fraction field is non-zero: a subnormal pattern, flushed to zero. */
  def isFlushed(x: UInt): Bool = isZero(x) && frac(x).orR
  /** Exponent field all ones. */
  def isInfOrNaN(x: UInt): Bool = exp(x).andR
  def isInf(x: UInt): Bool = isInfOrNaN(x) && frac(x) === 0.U
  def isNaN(x: UInt): Bool = isInfOrNaN(x) && frac(x) =/= 0.U
  /** The significand with its hidden bit, manWidth+1 bits; 0 for a zero. */
  def sig(x: UInt): UInt = Mux(isZero(x), 0.U, Cat(1.U(1.W), frac(x)))
}

object FloatFields {
  def apply(fmt: FloatFormat): FloatFields = new FloatFields(fmt)
}

private[fpu] object FUnpack {
  def apply(fmt: FloatFormat, bits: UInt): FUnpacked = {
    val f = FloatFields(fmt)
    val u = Wire(new FUnpacked(fmt))
    u.sign := f.sign(bits)
    u.isZero := f.isZero(bits)
    u.isInf := f.isInf(bits)
    u.isNaN := f.isNaN(bits)
    u.exp := f.exp(bits)
    u.sig := f.sig(bits)
    u
  }
}

private[fpu] object FPack {
  def inf(fmt: FloatFormat, sign: Bool): UInt = Cat(sign, fmt.expMax.U(fmt.expWidth.W), 0.U(fmt.manWidth.W))
  def zero(fmt: FloatFormat, sign: Bool): UInt = Cat(sign, 0.U((fmt.width - 1).W))
  def nan(fmt: FloatFormat): UInt = fmt.quietNaN.U(fmt.width.W)

  /** Rounds to nearest even and packs. The significand is 1.`frac` (`frac` is manWidth bits, the
    * leading one implied), `exp` the biased exponent of that leading one (any range), `guard` the
    * next bit below `frac` and `sticky` whether anything below the guard bit is nonzero. A rounded
    * exponent of expMax or more is infinity, 0 or less a zero (flush based on the rounded value),
    * both carrying `sign`. */
  def round(fmt: FloatFormat, sign: Bool, exp: SInt, frac: UInt, guard: Bool, sticky: Bool): UInt = {
    val up = guard && (sticky || frac(0))
    val next = frac +& up // carry out: 1.11..1 rounded up to 10.00..0, whose fraction is 0
    val e = exp +& next(fmt.manWidth).zext
    Mux(e >= fmt.expMax.S, inf(fmt, sign),
      Mux(e <= 0.S, zero(fmt, sign), Cat(sign, e(fmt.expWidth - 1, 0).asUInt, next(fmt.manWidth - 1, 0))))
  }
}

/** Optional pipeline registers at a unit's cut points: `cuts(i)` says whether cut i holds a
  * register. Data registers load only while the valid bit beside them is set. */
private[fpu] trait PipelineCuts { this: Module =>
  def cuts: Seq[Boolean]
  /** Number of register stages, the unit's latency in cycles. */
  def latency: Int = cuts.count(identity)

  protected def validAt(i: Int, v: Bool): Bool = if (cuts(i)) RegNext(v, false.B) else v
  protected def dataAt[T <: Data](i: Int, v: Bool, x: T): T = if (cuts(i)) RegEnable(x, v) else x

  /** `base` and, when some cut is left out, the cut pattern (e.g. `_c1011`). */
  protected def nameWithCuts(base: String): String =
    if (cuts.forall(identity)) base else base + "_c" + cuts.map(c => if (c) "1" else "0").mkString
}
