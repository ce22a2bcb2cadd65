package mapm.fpu

import chisel3._
import chisel3.util._
import mapm.numerics.FloatFormat

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
}

/** A rounding to nearest even split in two steps, so that a pipeline register may sit between
  * them. The significand is 1.`frac` (`frac` is manWidth bits, the leading one implied), `exp`
  * the biased exponent of that leading one (any range), `guard` the next bit below `frac` and
  * `sticky` whether anything below the guard bit is nonzero. A rounded exponent of expMax or more
  * is infinity, 0 or less a zero (flush based on the rounded value), both carrying `sign`.
  *
  * The increment is a carry-select over blocks of [[RoundPrep.Block]] bits. The first step
  * decides whether to round up, increments each block on its own, finds the carry into each block
  * (round up and every lower bit one) and out of the fraction, and decides for both the exponent
  * and the exponent plus one whether the result overflows or flushes. The second ([[finish]]) only
  * selects: each block or its increment, then by the carry out (1.11..1 rounded up to 10.00..0,
  * fraction 0) the exponent, overflow or flush. */
private[fpu] class RoundPrep(fmt: FloatFormat) extends Bundle {
  private val m = fmt.manWidth
  private val blocks = RoundPrep.ranges(m).length
  val sign = Bool()
  val frac = UInt(m.W)
  val fracInc = UInt(m.W)               // each block plus one, on its own
  val carries = UInt(blocks.W)          // carry into block k
  val carry = Bool()                    // carry out of the fraction
  val exp = UInt(fmt.expWidth.W)        // low bits of exp and of exp + 1
  val expUp = UInt(fmt.expWidth.W)
  val inf = Bool()                      // exp >= expMax; infUp: exp + 1 >= expMax
  val infUp = Bool()
  val zero = Bool()                     // exp <= 0; zeroUp: exp + 1 <= 0
  val zeroUp = Bool()
  val up = Bool()                       // the significand rounds up
  val inexact = Bool()                  // guard or sticky: the significand was rounded

  /** Whether the packed result's magnitude lies (above, below) the exact value's: an overflow to
    * infinity is above, a flush to zero below, else the rounding's direction. */
  def magnitudeDirection: (Bool, Bool) = {
    val overflow = Mux(carry, infUp, inf)
    val flush = Mux(carry, zeroUp, zero)
    (overflow || (!flush && up), flush || (!overflow && inexact && !up))
  }

  /** The packed result. */
  def finish: UInt = {
    val next = Cat(RoundPrep.ranges(m).zipWithIndex.reverse.map { case ((lo, hi), k) =>
      Mux(carries(k), fracInc(hi, lo), frac(hi, lo))
    })
    Mux(Mux(carry, infUp, inf), FPack.inf(fmt, sign),
      Mux(Mux(carry, zeroUp, zero), FPack.zero(fmt, sign),
        Cat(sign, Mux(carry, expUp, exp), next)))
  }
}

private[fpu] object RoundPrep {
  /** Bits per block of the rounding increment's carry-select. */
  val Block = 6

  /** The blocks' bit ranges (low, high) of an m-bit fraction, lowest first. */
  def ranges(m: Int): Seq[(Int, Int)] = (0 until m by Block).map(lo => (lo, math.min(m, lo + Block) - 1))

  def apply(fmt: FloatFormat, sign: Bool, exp: SInt, frac: UInt, guard: Bool, sticky: Bool): RoundPrep = {
    val r = Wire(new RoundPrep(fmt))
    val m = fmt.manWidth
    val up = guard && (sticky || frac(0))
    r.sign := sign
    r.frac := frac
    r.fracInc := Cat(ranges(m).reverse.map { case (lo, hi) => frac(hi, lo) + 1.U })
    r.carries := Cat(ranges(m).reverse.map { case (lo, _) => if (lo == 0) up else up && frac(lo - 1, 0).andR })
    r.carry := up && frac.andR
    r.up := up
    r.inexact := guard || sticky
    r.exp := exp(fmt.expWidth - 1, 0).asUInt
    r.expUp := (exp(fmt.expWidth - 1, 0).asUInt + 1.U)(fmt.expWidth - 1, 0)
    r.inf := exp >= fmt.expMax.S
    r.infUp := exp >= (fmt.expMax - 1).S
    r.zero := exp <= 0.S
    r.zeroUp := exp <= (-1).S
    r
  }
}

/** The last steps of the multiplier and the divider: normalized significand bits in, packed result
  * out. The step that formed `frac`, `guard`, `sticky` and `exp` ends; the next forms the rounding
  * ([[RoundPrep]]), the last selects it or the special result. */
private[fpu] object RoundTail {
  def apply(p: StepPipe, fmt: FloatFormat, special: Bool, specialBits: UInt, sign: Bool, exp: SInt,
            frac: UInt, guard: Bool, sticky: Bool): UInt = {
    val (special1, bits1, sign1) = (p(special), p(specialBits), p(sign))
    val (frac1, guard1, sticky1, exp1) = (p(frac), p(guard), p(sticky), p(exp))
    p.next()
    val prep = p(RoundPrep(fmt, sign1, exp1, frac1, guard1, sticky1))
    val (special2, bits2) = (p(special1), p(bits1))
    p.next()
    p.last(Mux(special2, bits2, prep.finish))
  }
}
