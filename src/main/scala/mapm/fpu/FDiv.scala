package mapm.fpu

import chisel3._
import chisel3.util._
import mapm.model.FloatFormat

/** Pipelined floating-point divider: out = a / b, correctly rounded to nearest even in format
  * `fmt`, bit-exact with [[mapm.model.SoftFloat.div]] (flush of zero-exponent inputs and of
  * results below the smallest normal, overflow to infinity, x / 0 = infinity, canonical NaN;
  * docs/fpu.md).
  *
  * The significands divide by **radix-2 SRT with a carry-save remainder**, one quotient digit in
  * {-1, 0, 1} per step, unrolled (docs/fpu.md, "The divider"). With the significands A and B as
  * (manWidth+1)-bit integers, the remainder W starts at A, the divisor is D = 2B and
  * |W| <= D holds throughout. Each step takes its digit from a 4-bit estimate of 2W (the top bits
  * of its sum and carry vectors added: digit 1 when the estimate is >= 0, 0 when it is -1/2, -1
  * below) and forms W' = 2W - q D with one row of full adders, so the step's delay does not
  * grow with the width. The digits are converted to binary on the fly (Q and Q - 1 kept side by
  * side). After manWidth + 3 digits one carry-propagate addition gives the remainder's sign, which
  * picks Q or Q - 1, and whether it is zero, the sticky bit.
  *
  * Steps ([[FDiv.weights]]), any of which a register may end ([[PipelinePlan]]):
  *  - unpack, special cases, exponent difference, the first remainder;
  *  - manWidth + 3 digit steps (26 at fp32);
  *  - the Kogge-Stone levels of the final remainder's addition;
  *  - the remainder's sign and zero test, Q or Q - 1, normalization, guard and sticky bits;
  *  - rounding: the block increments, then the carry select and the choice of overflow, flush or
  *    the packed result.
  *
  * Latency: `stages` cycles (the output is registered when stages >= 1), default
  * [[FDiv.defaultStages]]. Throughput: one operation per cycle; `out.valid` is `in.valid` delayed
  * by the latency.
  */
class FDiv(val fmt: FloatFormat, val stages: Int) extends Module with PlannedPipeline {
  def this(fmt: FloatFormat) = this(fmt, FDiv.defaultStages(fmt))
  def weights: Seq[Double] = FDiv.weights(fmt)
  override def desiredName: String = s"FDiv_${fmt.name}_s$stages"

  val io = IO(new Bundle {
    val in = Flipped(Valid(new FOperands(fmt)))
    val out = Valid(UInt(fmt.width.W))
  })

  private val m = fmt.manWidth
  private val digits = FDiv.digits(fmt)     // quotient digits: m + 3
  // Remainder vectors, two's complement mod 2^w: 2W and the estimate (above -3 D and at most 2 D)
  // need a sign bit at 2^(m+4).
  private val w = m + 5
  private val expW = fmt.expWidth + 3      // holds 1 - (expMax - 1) + bias - 1 .. expMax - 1 - 1 + bias, signed
  private val p = new StepPipe(cuts, io.in.valid)

  private class Side extends Bundle {
    val special = Bool()
    val specialBits = UInt(fmt.width.W)
    val sign = Bool()
    val exp = SInt(expW.W)
    val d = UInt(w.W)      // D = 2B
    val negD = UInt(w.W)   // -D, for the remainder's zero test
  }
  private class Rem extends Bundle {
    val s = UInt(w.W)      // W = s + c (mod 2^w)
    val c = UInt(w.W)
    val q = UInt(digits.W) // the digits so far, as Q and Q - 1 (mod 2^digits)
    val qm = UInt(digits.W)
  }

  // Step 0: specials, exponent difference, the first remainder W = A.
  val a = FUnpack(fmt, io.in.bits.a)
  val b = FUnpack(fmt, io.in.bits.b)
  val sign = a.sign ^ b.sign
  private val side0 = Wire(new Side)
  val invalid = a.isNaN || b.isNaN || (a.isInf && b.isInf) || (a.isZero && b.isZero)
  side0.special := a.isNaN || b.isNaN || a.isInf || b.isInf || a.isZero || b.isZero
  side0.specialBits := Mux(invalid, FPack.nan(fmt),
    Mux(a.isInf || b.isZero, FPack.inf(fmt, sign), FPack.zero(fmt, sign)))
  side0.sign := sign
  side0.exp := (a.exp.zext -& b.exp.zext) +& fmt.bias.S
  side0.d := Cat(b.sig, 0.U(1.W))
  side0.negD := 0.U(w.W) - Cat(b.sig, 0.U(1.W))
  private val rem0 = Wire(new Rem)
  rem0.s := a.sig
  rem0.c := 0.U
  rem0.q := 0.U
  rem0.qm := ((BigInt(1) << digits) - 1).U
  private var side = p(side0)
  private var rem = p(rem0)
  p.next()

  // The digit steps.
  for (_ <- 0 until digits) {
    val s2 = (rem.s << 1)(w - 1, 0)
    val c2 = (rem.c << 1)(w - 1, 0)
    // The estimate of 2W to one fraction bit (2^(m+1)): the top 4 bits of each vector, added mod 16.
    val est = (rem.s(w - 2, w - 5) +& rem.c(w - 2, w - 5))(3, 0)
    val plus = !est(3)              // estimate >= 0: digit 1
    val zero = est === "b1111".U    // estimate -1/2: digit 0; below: -1
    // -q D: for q = 1 the complement of D plus one (the carry vector's free low bit).
    val addend = Mux(plus, ~side.d, Mux(zero, 0.U(w.W), side.d))
    val next = Wire(new Rem)
    next.s := s2 ^ c2 ^ addend
    next.c := Cat(((s2 & c2) | (s2 & addend) | (c2 & addend))(w - 2, 0), plus)
    next.q := Mux(plus, Cat(rem.q, 1.U(1.W)), Mux(zero, Cat(rem.q, 0.U(1.W)), Cat(rem.qm, 1.U(1.W))))(digits - 1, 0)
    next.qm := Mux(plus, Cat(rem.q, 0.U(1.W)), Mux(zero, Cat(rem.qm, 1.U(1.W)), Cat(rem.qm, 0.U(1.W))))(digits - 1, 0)
    rem = p(next); side = p(side); p.next()
  }

  // The remainder W = s + c, one Kogge-Stone level per step.
  private val spans = PrefixAdd.spans(w, carryOut = false)
  private var add = PrefixAdd.start(rem.s, rem.c, false.B, w, carryOut = false)
  private var qs = rem
  for (d <- spans.drop(1)) { add = add.map(p(_)); qs = p(qs); side = p(side); p.next(); add = PrefixAdd.level(add, d) }
  private val wSum = p(PrefixAdd.sum(add)); qs = p(qs); side = p(side); p.next()

  // Q = floor(2^(m+2) A / B) in [2^(m+1), 2^(m+3)); the remainder is zero when W is 0 or -D.
  val negative = wSum(w - 1)
  val q = Mux(negative, qs.qm, qs.q)
  val remainder = wSum =/= 0.U && wSum =/= side.negD
  val top = q(digits - 1)
  val frac = Mux(top, q(m + 1, 2), q(m, 1))
  val guard = Mux(top, q(1), q(0))
  val sticky = remainder || (top && q(0))
  val exp = side.exp - (!top).zext
  private val fracR = p(frac); private val guardR = p(guard); private val stickyR = p(sticky)
  private val expR = p(exp); side = p(side); p.next()

  // Rounding.
  private val prep = p(RoundPrep(fmt, side.sign, expR, fracR, guardR, stickyR)); side = p(side); p.next()
  io.out.bits := p.last(Mux(side.special, side.specialBits, prep.finish))
  io.out.valid := p.finish()
}

object FDiv {
  /** Quotient digits: the hidden bit, the fraction, a guard bit and one more for the quotient's
    * range (the significands' quotient lies in (1/2, 2)). */
  def digits(fmt: FloatFormat): Int = fmt.manWidth + 3

  /** Estimated delay of each step (docs/fpu.md): a digit step is a 4-bit addition, the digit's
    * choice of addend and one full adder. */
  def weights(fmt: FloatFormat): Seq[Double] = {
    val adder = PrefixAdd.spans(fmt.manWidth + 4, carryOut = false).length
    Seq(1.5) ++ Seq.fill(digits(fmt))(2.0) ++ Seq.tabulate(adder)(i => if (i == 0) 1.0 else 0.5) ++
      Seq(2.0, 1.0, 1.5)
  }

  /** The default latency: [[FpuDepth.of]] at its default logic per stage. */
  def defaultStages(fmt: FloatFormat): Int = FpuDepth.of(fmt).div
}
