package mapm.fpu

import chisel3._
import chisel3.util._
import mapm.model.FloatFormat

/** Operands of [[FAdd]]: a and b, and `sub` to compute a - b instead of a + b. */
class FAddIn(fmt: FloatFormat) extends FOperands(fmt) {
  val sub = Bool()
}

/** Pipelined floating-point adder/subtractor: out = a + b (or a - b when `sub`), correctly rounded
  * to nearest even in format `fmt`, bit-exact with [[mapm.model.SoftFloat.add]] / `sub` (flush of
  * zero-exponent inputs and of results below the smallest normal, overflow to infinity, canonical
  * NaN; docs/fpu.md).
  *
  * Four stages, each ended by an optional register (cut), in this order:
  *  0. unpack, special cases, order the operands by magnitude, exponent difference;
  *  1. align the smaller significand (guard, round and sticky bits), add or subtract;
  *  2. leading-zero count and normalizing shift;
  *  3. round, overflow/flush, select special results.
  *
  * Latency: the number of cuts present, 4 by default ([[FAdd.stages]]). Throughput: one operation
  * per cycle; `out.valid` is `in.valid` delayed by the latency.
  */
class FAdd(val fmt: FloatFormat, val cuts: Seq[Boolean] = FAdd.defaultCuts) extends Module with PipelineCuts {
  require(cuts.length == FAdd.stages, s"FAdd has ${FAdd.stages} cut points, got ${cuts.length}")
  override def desiredName: String = nameWithCuts(s"FAdd_${fmt.name}")

  val io = IO(new Bundle {
    val in = Flipped(Valid(new FAddIn(fmt)))
    val out = Valid(UInt(fmt.width.W))
  })

  private val n = fmt.manWidth + 1
  private val shiftW = log2Ceil(n + 4)

  // Stage 0: unpack, specials, order by magnitude.
  val v0 = io.in.valid
  val a = FUnpack(fmt, io.in.bits.a)
  val b = FUnpack(fmt, io.in.bits.b)
  val bSign = b.sign ^ io.in.bits.sub
  val swap = Cat(b.exp, b.sig) > Cat(a.exp, a.sig) // zeros have exp = sig = 0
  val s0 = Wire(new Bundle {
    val special = Bool()
    val specialBits = UInt(fmt.width.W)
    val sign = Bool()
    val effSub = Bool()
    val bigExp = UInt(fmt.expWidth.W)
    val bigSig = UInt(n.W)
    val smallSig = UInt(n.W)
    val shift = UInt(shiftW.W)
  })
  val effSub = a.sign =/= bSign
  val invalid = a.isNaN || b.isNaN || (a.isInf && b.isInf && effSub)
  s0.special := a.isNaN || b.isNaN || a.isInf || b.isInf
  s0.specialBits := Mux(invalid, FPack.nan(fmt), FPack.inf(fmt, Mux(a.isInf, a.sign, bSign)))
  s0.sign := Mux(swap, bSign, a.sign)
  s0.effSub := effSub
  s0.bigExp := Mux(swap, b.exp, a.exp)
  s0.bigSig := Mux(swap, b.sig, a.sig)
  s0.smallSig := Mux(swap, a.sig, b.sig)
  val expDiff = Mux(swap, b.exp - a.exp, a.exp - b.exp)
  s0.shift := Mux(expDiff >= (n + 3).U, (n + 3).U, expDiff(math.min(fmt.expWidth, shiftW) - 1, 0))
  val v1 = validAt(0, v0)
  val r0 = dataAt(0, v0, s0)

  // Stage 1: align with guard, round and sticky bits; add or subtract (|big| >= |small|).
  val wide = Cat(r0.smallSig, 0.U((n + 6).W)) >> r0.shift // 2n+6 bits
  val aligned = wide(2 * n + 5, n + 3) | wide(n + 2, 0).orR
  val bigExt = Cat(r0.bigSig, 0.U(3.W))
  val s1 = Wire(new Bundle {
    val special = Bool()
    val specialBits = UInt(fmt.width.W)
    val sign = Bool()
    val effSub = Bool()
    val bigExp = UInt(fmt.expWidth.W)
    val sum = UInt((n + 4).W)
  })
  s1.special := r0.special
  s1.specialBits := r0.specialBits
  s1.sign := r0.sign
  s1.effSub := r0.effSub
  s1.bigExp := r0.bigExp
  s1.sum := Mux(r0.effSub, bigExt - aligned, bigExt +& aligned)
  val v2 = validAt(1, v1)
  val r1 = dataAt(1, v1, s1)

  // Stage 2: normalize so that the leading one sits at bit n+3 (a right shift of the reversed sum,
  // which keeps the width); that bit is then implied.
  val lz = PriorityEncoder(r1.sum.asBools.reverse)
  val s2 = Wire(new Bundle {
    val special = Bool()
    val specialBits = UInt(fmt.width.W)
    val sign = Bool()
    val zero = Bool()
    val zeroSign = Bool()
    val exp = SInt((math.max(fmt.expWidth, shiftW) + 2).W)
    val norm = UInt((n + 3).W)
  })
  s2.special := r1.special
  s2.specialBits := r1.specialBits
  s2.sign := r1.sign
  s2.zero := r1.sum === 0.U
  s2.zeroSign := r1.sign && !r1.effSub // exact zero: -0 only for (-0) + (-0)
  s2.exp := (r1.bigExp +& 1.U).zext - lz.zext
  s2.norm := Cat((Cat(r1.sum(n + 2, 0).asBools) >> lz).asBools) // reverse, shift right, reverse
  val v3 = validAt(2, v2)
  val r2 = dataAt(2, v2, s2)

  // Stage 3: round and pack.
  val rounded = FPack.round(fmt, r2.sign, r2.exp, r2.norm(n + 2, 4), r2.norm(3), r2.norm(2, 0).orR)
  val result = Mux(r2.special, r2.specialBits, Mux(r2.zero, FPack.zero(fmt, r2.zeroSign), rounded))
  io.out.valid := validAt(3, v3)
  io.out.bits := dataAt(3, v3, result)
}

object FAdd {
  /** Cut points (optional register stages); the default latency. */
  val stages = 4
  val defaultCuts: Seq[Boolean] = Seq.fill(stages)(true)
}
