package mapm.fpu

import chisel3._
import chisel3.util._
import mapm.util.StageClocks
import chisel3.experimental.hierarchy.{instantiable, public}
import mapm.numerics.FloatFormat

/** Operands of [[FAdd]]: a and b, and `sub` to compute a - b instead of a + b. */
class FAddIn(fmt: FloatFormat) extends FOperands(fmt) {
  val sub = Bool()
}

/** Pipelined floating-point adder/subtractor: out = a + b (or a - b when `sub`), correctly rounded
  * to nearest even in format `fmt`, bit-exact with [[mapm.numerics.SoftFloat.add]] / `sub` (flush of
  * zero-exponent inputs and of results below the smallest normal, overflow to infinity, canonical
  * NaN; docs/fpu.md).
  *
  * Steps ([[FAdd.weights]]), any of which a register may end ([[PipelinePlan]]):
  *  - unpack, special cases, magnitude order and both exponent differences;
  *  - swap by magnitude, and the alignment shift's upper levels;
  *  - its lower levels, with guard, round and sticky bits;
  *  - the Kogge-Stone levels of the (manWidth+4)-bit addition or subtraction (5 at fp32);
  *  - the sum bits and the leading-zero count;
  *  - the normalizing shift's upper levels and the exponent, then its lower levels;
  *  - rounding: the block increments, then the carry select and the choice of overflow, flush or
  *    the packed result.
  *
  * With `direction` the unit also tells whether the result lies above the exact sum (`above`,
  * beside `out`: rounded up in value, an overflow to +infinity, or a flush to zero of a negative
  * sum; false when exact; meaningful for finite operands), which lets a comparison of the rounded
  * sum decide as the exact sum would (the conventional TSA). With `stallable` an `en` input freezes every register
  * while low (the output holds). With `gated` the data registers of stage k run on `clocks(k)`,
  * which the pipeline around the unit gates ([[StepPipe]], [[mapm.util.StageGates]]).
  *
  * Latency: `stages` cycles (the output is registered when stages >= 1), default
  * [[FAdd.defaultStages]]; enabled cycles when stallable. Throughput: one operation per cycle;
  * `out.valid` is `in.valid` delayed by the latency.
  */
@instantiable
class FAdd(val fmt: FloatFormat, val stages: Int, val stallable: Boolean = false, val direction: Boolean = false,
           val gated: Boolean = false) extends Module with PlannedPipeline {
  def this(fmt: FloatFormat) = this(fmt, FAdd.defaultStages(fmt))
  def weights: Seq[Double] = FAdd.weights(fmt)
  override def desiredName: String =
    s"FAdd_${fmt.name}_s$stages${if (stallable) "_en" else ""}${if (direction) "_dir" else ""}${StageClocks.suffix(gated)}"

  @public val io = IO(new Bundle {
    val in = Flipped(Valid(new FAddIn(fmt)))
    val out = Valid(UInt(fmt.width.W))
    /** Pipeline enable (stallable units only). */
    val en = if (stallable) Some(Input(Bool())) else None
    /** The result lies above the exact sum (units with `direction` only). */
    val above = if (direction) Some(Output(Bool())) else None
    /** clocks(k): the clock of register stage k's data (stage-gated units only). */
    val clocks = StageClocks.port(stages, gated)
  })

  private val n = fmt.manWidth + 1
  private val shiftW = log2Ceil(n + 4)
  private val expW = math.max(fmt.expWidth, shiftW) + 2
  private val p = new StepPipe(cuts, io.in.valid, io.en, new StageClocks(io.clocks))

  private class Side extends Bundle {
    val special = Bool()
    val specialBits = UInt(fmt.width.W)
    val sign = Bool()
    val effSub = Bool()
    val bigExp = UInt(fmt.expWidth.W)
  }

  // Step 0: unpack, specials, order by magnitude, both exponent differences (clamped).
  val a = FUnpack(fmt, io.in.bits.a)
  val b = FUnpack(fmt, io.in.bits.b)
  val bSign = b.sign ^ io.in.bits.sub
  val swap = Cat(b.exp, b.sig) > Cat(a.exp, a.sig) // zeros have exp = sig = 0
  val effSub = a.sign =/= bSign
  val invalid = a.isNaN || b.isNaN || (a.isInf && b.isInf && effSub)
  private def clamp(d: UInt): UInt = Mux(d >= (n + 3).U, (n + 3).U, d(math.min(fmt.expWidth, shiftW) - 1, 0))
  private val special = p(a.isNaN || b.isNaN || a.isInf || b.isInf)
  private val specialBits = p(Mux(invalid, FPack.nan(fmt), FPack.inf(fmt, Mux(a.isInf, a.sign, bSign))))
  private val (swapR, effSubR) = (p(swap), p(effSub))
  private val (aSign, bSignR, aExp, bExp) = (p(a.sign), p(bSign), p(a.exp), p(b.exp))
  private val (aSig, bSig) = (p(a.sig), p(b.sig))
  private val (shiftAB, shiftBA) = (p(clamp(a.exp - b.exp)), p(clamp(b.exp - a.exp)))
  p.next()

  // The operands in magnitude order.
  private val side1 = Wire(new Side)
  side1.special := special
  side1.specialBits := specialBits
  side1.sign := Mux(swapR, bSignR, aSign)
  side1.effSub := effSubR
  side1.bigExp := Mux(swapR, bExp, aExp)
  private var side = side1

  // Align the smaller significand in a word of 2n+6 bits, which loses nothing (shift <= n+3):
  // upper levels, then lower levels with guard, round and sticky bits.
  private val lowBits = shiftW / 2
  private def lowMask(x: UInt): UInt = x(lowBits - 1, 0)
  private val shift = Mux(swapR, shiftBA, shiftAB)
  private val coarse = Cat(Mux(swapR, aSig, bSig), 0.U((n + 6).W)) >> (shift >> lowBits << lowBits)
  private val bigSig1 = p(Mux(swapR, bSig, aSig))
  private val wide1 = p(coarse(2 * n + 5, 0)); private val fine = p(lowMask(shift)); side = p(side); p.next()
  private val wide = wide1 >> fine
  private val aligned = p(wide(2 * n + 5, n + 3) | wide(n + 2, 0).orR)
  private val bigExt = p(Cat(bigSig1, 0.U(3.W))); side = p(side); p.next()

  // The addition (big >= small, so a subtraction is big + ~small + 1 without its carry out).
  // The last level's register holds the sum bits rather than the prefix state.
  private val spans = PrefixAdd.spans(n + 3)
  private var add = PrefixAdd.start(bigExt, Mux(side.effSub, ~aligned, aligned), side.effSub, n + 3)
  for (d <- spans.drop(1)) { add = add.map(p(_)); side = p(side); p.next(); add = PrefixAdd.level(add, d) }
  private val total = p(PrefixAdd.sum(add)); side = p(side); p.next()
  private val sum = Cat(total(n + 3) && !side.effSub, total(n + 2, 0)) // n+4 bits

  // Leading zeros and zero result.
  private val lz = PriorityEncoder(sum.asBools.reverse)
  private val sumR = p(sum(n + 2, 0)); private val lzR = p(lz) // bit n+3 leaves in the shift: the implied one, or 0
  private val zero = p(sum === 0.U)
  private val zeroSign = p(side.sign && !side.effSub) // exact zero: -0 only for (-0) + (-0)
  side = p(side); p.next()

  /** x shifted left by `amount` within its own width: a right shift of the reversed word (the
    * reversal as bit lists, which CIRCT emits as plain wiring). */
  private def shiftLeft(x: UInt, amount: UInt): UInt = Cat((Cat(x.asBools) >> amount).asBools)

  // Normalize so that the leading one sits at bit n+3 (then implied): upper, then lower levels;
  // the exponent beside the upper levels.
  private val norm1 = p(shiftLeft(sumR, lzR >> lowBits << lowBits))
  private val lzFine = p(lowMask(lzR))
  private val exp2 = p((side.bigExp +& 1.U).zext - lzR.zext)
  private val (zero2, zeroSign2) = (p(zero), p(zeroSign)); side = p(side); p.next()
  private val norm = p(shiftLeft(norm1, lzFine))
  private val (zero3, exp3, zeroSign3) = (p(zero2), p(exp2), p(zeroSign2)); side = p(side); p.next()

  // Rounding.
  private val prep = p(RoundPrep(fmt, side.sign, exp3.pad(expW), norm(n + 2, 4), norm(3), norm(2, 0).orR))
  private val (zero4, zeroSign4) = (p(zero3), p(zeroSign3)); side = p(side); p.next()
  private val (magAbove, magBelow) = prep.magnitudeDirection
  private val aboveOut = p(!side.special && !zero4 && Mux(side.sign, magBelow, magAbove))
  io.out.bits := p.last(Mux(side.special, side.specialBits, Mux(zero4, FPack.zero(fmt, zeroSign4), prep.finish)))
  io.above.foreach(_ := aboveOut)
  io.out.valid := p.finish()
}

object FAdd {
  /** Estimated delay of each step (docs/fpu.md). */
  def weights(fmt: FloatFormat): Seq[Double] = {
    val adder = PrefixAdd.spans(fmt.manWidth + 4).length
    Seq(2.0, 1.5, 1.5) ++ Seq.tabulate(adder)(i => if (i == 0) 1.0 else 0.5) ++ Seq(2.0, 1.0, 1.0, 1.5, 1.5)
  }

  /** The default latency: [[FpuDepth.of]] at its default logic per stage. */
  def defaultStages(fmt: FloatFormat): Int = FpuDepth.of(fmt).add
}
