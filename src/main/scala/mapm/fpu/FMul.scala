package mapm.fpu

import chisel3._
import chisel3.util._
import mapm.util.StageClocks
import chisel3.experimental.hierarchy.{instantiable, public}
import mapm.numerics.FloatFormat

/** Pipelined floating-point multiplier: out = a * b, correctly rounded to nearest even in format
  * `fmt`, bit-exact with [[mapm.numerics.SoftFloat.mul]] (flush of zero-exponent inputs and of
  * results below the smallest normal, overflow to infinity, canonical NaN; docs/fpu.md).
  *
  * Steps ([[FMul.weights]]), any of which a register may end ([[PipelinePlan]]):
  *  - unpack, special cases, exponent sum, the significands' partial products and the first
  *    Dadda level;
  *  - the other Dadda levels, down to two rows (7 levels in all at fp32);
  *  - the Kogge-Stone levels of the final 2(manWidth+1)-bit addition (6 at fp32);
  *  - the sum bits, one-bit normalization, guard and sticky bits;
  *  - rounding: the block increments, then the carry select and the choice of overflow, flush or
  *    the packed result.
  *
  * With `gated` the data registers of register stage k run on `clocks(k)`, which the pipeline
  * around the unit gates ([[StepPipe]], [[mapm.util.StageGates]]).
  *
  * With `square` it is a squarer: the caller gives the same operand on both ports (an assertion
  * checks it in simulation), the special cases, sign and exponent come from both as before, and
  * the significand's partial products from `a` alone, folded about the diagonal
  * ([[Dadda.squareProducts]]: 300 bits instead of 576 at fp32, 5 Dadda levels instead of 7), so
  * that the registers inside the tree hold about half the bits. The product is the same
  * correctly rounded a * a. It needs as many steps as `stages` ([[FMul.squareFits]]).
  *
  * Latency: `stages` cycles (the output is registered when stages >= 1), default
  * [[FMul.defaultStages]]. Throughput: one operation per cycle; `out.valid` is `in.valid` delayed
  * by the latency.
  */
@instantiable
class FMul(val fmt: FloatFormat, val stages: Int, val gated: Boolean = false, val square: Boolean = false) extends Module with PlannedPipeline {
  def this(fmt: FloatFormat) = this(fmt, FMul.defaultStages(fmt))
  require(!square || FMul.squareFits(fmt, stages),
    s"FMul: a squarer of ${fmt.name} has ${FMul.weights(fmt, square = true).length} steps, fewer than $stages stages")
  def weights: Seq[Double] = FMul.weights(fmt, square)
  override def desiredName: String = s"FMul_${fmt.name}_s$stages${if (square) "_sq" else ""}${StageClocks.suffix(gated)}"

  @public val io = IO(new Bundle {
    val in = Flipped(Valid(new FOperands(fmt)))
    val out = Valid(UInt(fmt.width.W))
    /** clocks(k): the clock of register stage k's data (stage-gated units only). */
    val clocks = StageClocks.port(stages, gated)
  })

  private val n = fmt.manWidth + 1
  private val expW = fmt.expWidth + 3 // holds 2 - bias .. 2*expMax - bias, signed
  private val p = new StepPipe(cuts, io.in.valid, clocks = new StageClocks(io.clocks))

  private class Side extends Bundle {
    val special = Bool()
    val specialBits = UInt(fmt.width.W)
    val sign = Bool()
    val exp = SInt(expW.W)
  }

  // Step 0: specials, exponent sum, partial products and the first Dadda level.
  val a = FUnpack(fmt, io.in.bits.a)
  val b = FUnpack(fmt, io.in.bits.b)
  if (square) assert(!io.in.valid || io.in.bits.a === io.in.bits.b, "FMul squarer: the operands differ")
  private val side0 = Wire(new Side)
  val sign = a.sign ^ b.sign
  val invalid = a.isNaN || b.isNaN || (a.isInf && b.isZero) || (b.isInf && a.isZero)
  side0.special := a.isNaN || b.isNaN || a.isInf || b.isInf || a.isZero || b.isZero
  side0.specialBits := Mux(invalid, FPack.nan(fmt),
    Mux(a.isInf || b.isInf, FPack.inf(fmt, sign), FPack.zero(fmt, sign)))
  side0.sign := sign
  side0.exp := (a.exp +& b.exp).zext - fmt.bias.S

  private var side = side0
  private val targets = FMul.tree(n, square)
  private val products = if (square) Dadda.squareProducts(a.sig) else Dadda.partialProducts(a.sig, b.sig)
  private var cols = targets.headOption.fold(products)(Dadda.level(products, _))
  private def crossTree(): Unit = { cols = cols.map(_.map(p(_))); side = p(side); p.next() }
  crossTree()
  for (t <- targets.drop(1)) { cols = Dadda.level(cols, t); crossTree() }

  // The final addition, one Kogge-Stone level per step; the last level's register holds the sum.
  private val (rowA, rowB) = Dadda.rows(cols, 2 * n)
  // The product fits in 2n bits: no carry out.
  private val spans = PrefixAdd.spans(2 * n, carryOut = false)
  private var add = PrefixAdd.start(rowA, rowB, false.B, 2 * n, carryOut = false)
  for (d <- spans.drop(1)) { add = add.map(p(_)); side = p(side); p.next(); add = PrefixAdd.level(add, d) }
  private val prod = p(PrefixAdd.sum(add)); side = p(side); p.next()

  // The product is in [2^(2n-2), 2^(2n)): keep the n-1 fraction bits below its leading one.
  val top = prod(2 * n - 1)
  val frac = Mux(top, prod(2 * n - 2, n), prod(2 * n - 3, n - 1))
  val guard = Mux(top, prod(n - 1), prod(n - 2))
  val sticky = (if (n >= 3) prod(n - 3, 0).orR else false.B) || (top && prod(n - 2))
  val exp = side.exp + top.zext
  // Rounding.
  io.out.bits := RoundTail(p, fmt, side.special, side.specialBits, side.sign, exp, frac, guard, sticky)
  io.out.valid := p.finish()
}

object FMul {
  /** Estimated delay of each step (docs/fpu.md). */
  def weights(fmt: FloatFormat, square: Boolean = false): Seq[Double] = {
    val n = fmt.manWidth + 1
    val levels = tree(n, square).length
    val adder = PrefixAdd.spans(2 * n, carryOut = false).length
    Seq(1.0 + (if (levels > 0) 1.0 else 0.0)) ++ Seq.fill(levels - 1 max 0)(1.0) ++
      Seq.tabulate(adder)(i => if (i == 0) 1.0 else 0.5) ++ Seq(1.5, 1.0, 1.5)
  }

  /** The Dadda levels' target heights for `n`-bit significands (a squarer's tree is shorter). */
  private def tree(n: Int, square: Boolean): Seq[Int] = Dadda.targets(if (square) Dadda.squareHeight(n) else n)

  /** Whether a squarer of `fmt` has at least `stages` steps to place its registers in. */
  def squareFits(fmt: FloatFormat, stages: Int): Boolean = weights(fmt, square = true).length >= stages

  /** The default latency: [[FpuDepth.of]] at its default logic per stage. */
  def defaultStages(fmt: FloatFormat): Int = FpuDepth.of(fmt).mul
}
