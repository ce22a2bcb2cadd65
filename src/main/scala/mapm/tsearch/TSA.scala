package mapm.tsearch

import chisel3._
import chisel3.util._
import mapm.arith.P2S
import mapm.fpu.FloatFields
import mapm.numerics.{Arith, FloatFormat, TsaModel}

/** One tree-search comparison: query coordinate p, kernel radius h, split position s (bit
  * patterns of `fmt`) and an opaque tag that comes back with the outcome. */
class TsaRequest(fmt: FloatFormat, tagWidth: Int) extends Bundle {
  val p = UInt(fmt.width.W)
  val h = UInt(fmt.width.W)
  val s = UInt(fmt.width.W)
  val tag = UInt(tagWidth.W)
}

/** The outcome: traverse the left child (p-h < s), the right child (p+h > s), and whether an
  * input was invalid (negative non-zero, infinite or NaN; both TC bits are then 1). */
class TsaResponse(tagWidth: Int) extends Bundle {
  val tcl = Bool()
  val tcr = Bool()
  val error = Bool()
  val tag = UInt(tagWidth.W)
}

/** A tree-search unit's ports: one comparison in, its outcome out; with `stallable` an `en`
  * input that freezes the unit while low. */
class TsaIO(fmt: FloatFormat, tagWidth: Int, stallable: Boolean) extends Bundle {
  val in = Flipped(Valid(new TsaRequest(fmt, tagWidth)))
  val out = Valid(new TsaResponse(tagWidth))
  /** Pipeline enable (stallable units only). */
  val en = if (stallable) Some(Input(Bool())) else None
}

/** A tree-search unit, online ([[TSA]]) or conventional ([[ConvTSA]]): TC_L = (p - h < s) and
  * TC_R = (p + h > s), exactly, at a fixed latency, one comparison per cycle. */
abstract class TsaUnit extends Module {
  val io: TsaIO
  /** Cycles from an accepted request to its response. */
  val latency: Int
}

object TsaUnit {
  /** An operand the unit refuses: infinite or NaN, or negative and not zero. */
  def invalid(f: FloatFields, x: UInt): Bool = f.isInfOrNaN(x) || (f.sign(x) && !f.isZero(x))

  /** The tree-search unit of arithmetic `arith`: the online [[TSA]], or the [[ConvTSA]] whose
    * adders have `addStages` stages (`FpuDepth.add`). */
  def apply(fmt: FloatFormat, tagWidth: Int, stallable: Boolean, arith: Arith, addStages: Int): TsaUnit = arith match {
    case Arith.Online => new TSA(fmt, tagWidth, stallable)
    case Arith.Conventional => new ConvTSA(fmt, tagWidth, stallable, addStages)
  }

  /** The module name of [[apply]]'s unit. */
  def name(fmt: FloatFormat, tagWidth: Int, stallable: Boolean, arith: Arith, addStages: Int): String = arith match {
    case Arith.Online => s"TSA_${fmt.name}_t$tagWidth${if (stallable) "_en" else ""}"
    case Arith.Conventional => ConvTSA.name(fmt, tagWidth, stallable, addStages)
  }

  /** The latency of [[apply]]'s unit. */
  def latency(fmt: FloatFormat, arith: Arith, addStages: Int): Int = arith match {
    case Arith.Online => TsaModel.latency(fmt)
    case Arith.Conventional => ConvTSA.latency(addStages)
  }
}

/** Tree Search Accelerator (3.4): TC_L = (p - h < s) and TC_R = (p + h > s), exactly, for
  * non-negative finite p, h, s in any [[FloatFormat]] (exponent field 0 is the value 0, -0 is 0).
  *
  * Structure (Figure 3.12): [[ShiftAmountLogic]] and three [[ShiftRight]] align the three
  * significands to the largest exponent into words of W = manWidth + 3 bits (hidden bit,
  * mantissa, one guard bit, one sticky bit: the two extra bits make the decisions exact, see
  * [[mapm.numerics.TsaModel]]), in four register stages: field extraction, the input check and the
  * Shift Amount Logic's subtractors in the first, its selection and the decoding of each amount
  * into shifter levels in the second, the three Shift Right units' upper levels in the third
  * ([[ShiftRight.coarse]]) and their lower and additional levels in the fourth
  * ([[ShiftRight.fine]]) (one stage held all of it, the unit's critical path; docs/cost.md);
  * three [[P2S]] turn the words into skewed bit streams; two W-slice
  * [[PipelinedComparator]]s decide p - h < s (TC_L) and s - h < p (TC_R, p and s swapped). The
  * valid bit, the tag and the error flag travel beside the slices.
  *
  * Latency: W + 4 = manWidth + 7 cycles (30 for fp32): four alignment stages and one cycle per
  * slice; the dissertation's manWidth + 2 has no guard and sticky slices and one alignment
  * cycle. Throughput: one operation per cycle, no stalls. `bits` of the output are meaningful
  * only while it is valid.
  *
  * With `stallable` (the Tree Search Module's use, 3.7) an `en` input freezes the whole pipeline
  * while low: no register changes, the output holds, and `in` is not taken (the driver presents an
  * operation only while `en` is high). Latency then counts enabled cycles.
  */
class TSA(fmt: FloatFormat, tagWidth: Int, stallable: Boolean = false) extends TsaUnit {
  require(tagWidth >= 1, s"tag width must be at least 1, got $tagWidth")
  override def desiredName = TsaUnit.name(fmt, tagWidth, stallable, Arith.Online, 0)

  /** The alignment the hardware builds (guard bits, sticky bit), shared with the model. */
  private val al = TsaModel.Alignment.exact
  /** Aligned word width, the number of comparator slices. */
  val wordWidth: Int = al.wordWidth(fmt)
  /** Cycles from an accepted request to its response. */
  val latency: Int = TsaModel.latency(fmt)

  val io = IO(new TsaIO(fmt, tagWidth, stallable))
  private val enable = io.en.getOrElse(true.B)
  /** `Pipe` whose registers move only while `enable` is high. */
  private def stage[T <: Data](in: Valid[T], n: Int): Valid[T] =
    (0 until n).foldLeft(in) { (v, _) =>
      val r = Wire(Valid(chiselTypeOf(v.bits)))
      r.valid := RegEnable(v.valid, false.B, enable)
      r.bits := RegEnable(v.bits, enable)
      r
    }

  // Stage 0 (combinational): fields, input check, the Shift Amount Logic's three subtractors.
  private val operands = Seq(io.in.bits.p, io.in.bits.h, io.in.bits.s)
  private val f = FloatFields(fmt)
  private def invalid(x: UInt) = TsaUnit.invalid(f, x)
  private val differences = ShiftAmountLogic.differences(f.exp(io.in.bits.p), f.exp(io.in.bits.h), f.exp(io.in.bits.s))

  class Meta extends Bundle {
    val tag = UInt(tagWidth.W)
    val error = Bool()
  }
  val meta = Wire(new Meta)
  meta.tag := io.in.bits.tag
  meta.error := operands.map(invalid).reduce(_ || _)
  private val entering = Wire(Valid(new Meta))
  entering.valid := io.in.valid
  entering.bits := meta

  // Stage 1: significands and differences registered; the Shift Amount Logic's selection (Table
  // 3.4) and each amount decoded into its shifter's levels.
  private val sigWidth = fmt.manWidth + 1 + al.guardBits
  private val sigIn = operands.map(x => if (al.guardBits == 0) f.sig(x) else Cat(f.sig(x), 0.U(al.guardBits.W)))
  private val sig1 = sigIn.map(RegEnable(_, enable))
  private val amounts = ShiftAmountLogic.select(differences.map(RegEnable(_, enable)))
  private val dist = amounts.map(si => ShiftRight.decode(si, sigWidth, fmt.expWidth + 1))

  // Stage 2: significands and decoded distances registered; the Shift Right units' upper levels.
  // Stage 3: the partly shifted words registered; their lower levels and the additional level.
  private val split = dist.head.levels / 2
  private val dist2 = dist.map(RegEnable(_, enable))
  private val partial = sig1.map(RegEnable(_, enable)).zip(dist2).map { case (sig, d) => RegEnable(ShiftRight.coarse(sig, d, split), enable) }
  val aligned = partial.zip(dist2).map { case (p, d) =>
    val (word, sticky) = ShiftRight.fine(p, (0 until split).map(i => RegEnable(d.level(i), enable)), RegEnable(d.extra, enable))
    if (al.sticky) Cat(word, sticky) else word
  }

  // Stage 4: aligned words registered; then bit-serial through P2S into the slices.
  val alignedReg = aligned.map(RegEnable(_, enable))
  val alignedMeta = stage(entering, 4)
  val Seq(ps, hs, ss) = alignedReg.map { w =>
    val p2s = Module(new P2S(wordWidth, stallable))
    p2s.io.in := w
    p2s.io.en.foreach(_ := enable)
    p2s.io.out
  }

  val cmpL = Module(new PipelinedComparator(wordWidth, stallable)) // p - h < s
  cmpL.io.a := ps; cmpL.io.b := hs; cmpL.io.c := ss
  val cmpR = Module(new PipelinedComparator(wordWidth, stallable)) // s - h < p, i.e. p + h > s
  cmpR.io.a := ss; cmpR.io.b := hs; cmpR.io.c := ps
  Seq(cmpL, cmpR).foreach(_.io.en.foreach(_ := enable))

  // Valid, tag and error beside the slices, leaving with the comparators' last stage.
  val leaving = stage(alignedMeta, wordWidth)
  io.out.valid := leaving.valid
  io.out.bits.tag := leaving.bits.tag
  io.out.bits.error := leaving.bits.error
  io.out.bits.tcl := cmpL.io.less || leaving.bits.error
  io.out.bits.tcr := cmpR.io.less || leaving.bits.error
}
