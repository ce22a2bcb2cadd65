package mapm.fpu

import chisel3._
import chisel3.util._
import mapm.util.StageClocks
import mapm.numerics.FloatFormat

/** Pipelined floating-point divider: out = a / b, correctly rounded to nearest even in format
  * `fmt`, bit-exact with [[mapm.numerics.SoftFloat.div]] (flush of zero-exponent inputs and of
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
  * side, each register only as wide as the bits that still reach the quotient). After manWidth + 3 digits one carry-propagate addition gives the remainder's sign, which
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
  * With `gated` the data registers of register stage k run on `clocks(k)`, which the pipeline
  * around the unit gates ([[StepPipe]], [[mapm.util.StageGates]]).
  *
  * Latency: `stages` cycles (the output is registered when stages >= 1), default
  * [[FDiv.defaultStages]]. Throughput: one operation per cycle; `out.valid` is `in.valid` delayed
  * by the latency.
  */
class FDiv(val fmt: FloatFormat, val stages: Int, val gated: Boolean = false) extends Module with PlannedPipeline {
  def this(fmt: FloatFormat) = this(fmt, FDiv.defaultStages(fmt))
  def weights: Seq[Double] = FDiv.weights(fmt)
  override def desiredName: String = s"FDiv_${fmt.name}_s$stages${StageClocks.suffix(gated)}"

  val io = IO(new Bundle {
    val in = Flipped(Valid(new FOperands(fmt)))
    val out = Valid(UInt(fmt.width.W))
    /** clocks(k): the clock of register stage k's data (stage-gated units only). */
    val clocks = StageClocks.port(stages, gated)
  })

  private val m = fmt.manWidth
  private val digits = FDiv.digits(fmt)     // quotient digits: m + 3
  // The remainder vectors hold W mod 2^v: |W| <= D < 2^(m+2) needs a sign bit at 2^(m+3). Their
  // doubles 2W, and the estimate (above -3 D and at most 2 D), are read mod 2^(v+1).
  private val v = m + 4
  private val expW = fmt.expWidth + 3      // holds 1 - (expMax - 1) + bias - 1 .. expMax - 1 - 1 + bias, signed
  private val p = new StepPipe(cuts, io.in.valid, clocks = new StageClocks(io.clocks))

  private class Side extends Bundle {
    val special = Bool()
    val specialBits = UInt(fmt.width.W)
    val sign = Bool()
    val exp = SInt(expW.W)
    val d = UInt(v.W)      // D = 2B
    val negD = UInt(v.W)   // -D, for the remainder's zero test
  }
  /** The remainder after `j` digits, and the digits as Q and Q - 1: their low j bits, the only ones
    * that reach the final quotient (mod 2^digits) through the digits still to come. */
  private class Rem(j: Int) extends Bundle {
    val s = UInt(v.W)      // W = s + c (mod 2^v)
    val c = UInt(v.W)
    val q = UInt(j.W)
    val qm = UInt(j.W)
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
  side0.negD := 0.U(v.W) - Cat(b.sig, 0.U(1.W))
  private var side = p(side0)
  private var (ws, wc) = (p(a.sig.pad(v)), p(0.U(v.W)))
  p.next()

  // The digit steps. Q and Q - 1 start as 0 and -1: one bit each is all the first step reads.
  private var (q, qm) = (0.U(1.W), 1.U(1.W))
  for (j <- 1 to digits) {
    // 2W mod 2^v (the sum and carry vectors shifted), and its estimate to one fraction bit
    // (2^(m+1)) mod 2^(v+1): the top 4 bits of each doubled vector, added mod 16.
    val (s2, c2) = (Cat(ws(v - 2, 0), 0.U(1.W)), Cat(wc(v - 2, 0), 0.U(1.W)))
    val est = (ws(v - 1, v - 4) +& wc(v - 1, v - 4))(3, 0)
    val plus = !est(3)              // estimate >= 0: digit 1
    val zero = est === "b1111".U    // estimate -1/2: digit 0; below: -1
    // -q D: for q = 1 the complement of D plus one (the carry vector's free low bit).
    val addend = Mux(plus, ~side.d, Mux(zero, 0.U(v.W), side.d))
    val next = Wire(new Rem(j))
    next.s := s2 ^ c2 ^ addend
    next.c := Cat(((s2 & c2) | (s2 & addend) | (c2 & addend))(v - 2, 0), plus)
    next.q := Mux(plus, Cat(q, 1.U(1.W)), Mux(zero, Cat(q, 0.U(1.W)), Cat(qm, 1.U(1.W))))(j - 1, 0)
    next.qm := Mux(plus, Cat(q, 0.U(1.W)), Mux(zero, Cat(qm, 1.U(1.W)), Cat(qm, 0.U(1.W))))(j - 1, 0)
    val r = p(next); side = p(side); p.next()
    ws = r.s; wc = r.c; q = r.q; qm = r.qm
  }

  // The remainder W = s + c, one Kogge-Stone level per step.
  private val spans = PrefixAdd.spans(v, carryOut = false)
  private var add = PrefixAdd.start(ws, wc, false.B, v, carryOut = false)
  for (d <- spans.drop(1)) { add = add.map(p(_)); q = p(q); qm = p(qm); side = p(side); p.next(); add = PrefixAdd.level(add, d) }
  private val wSum = p(PrefixAdd.sum(add)); q = p(q); qm = p(qm); side = p(side); p.next()

  // Q = floor(2^(m+2) A / B) in [2^(m+1), 2^(m+3)); the remainder is zero when W is 0 or -D.
  val negative = wSum(v - 1)
  val quotient = Mux(negative, qm, q)
  val remainder = wSum =/= 0.U && wSum =/= side.negD
  val top = quotient(digits - 1)
  val frac = Mux(top, quotient(m + 1, 2), quotient(m, 1))
  val guard = Mux(top, quotient(1), quotient(0))
  val sticky = remainder || (top && quotient(0))
  val exp = side.exp - (!top).zext
  // Rounding.
  io.out.bits := RoundTail(p, fmt, side.special, side.specialBits, side.sign, exp, frac, guard, sticky)
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
