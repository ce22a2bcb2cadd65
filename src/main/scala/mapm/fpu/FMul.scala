package mapm.fpu

import chisel3._
import chisel3.util._
import mapm.model.FloatFormat

/** Pipelined floating-point multiplier: out = a * b, correctly rounded to nearest even in format
  * `fmt`, bit-exact with [[mapm.model.SoftFloat.mul]] (flush of zero-exponent inputs and of
  * results below the smallest normal, overflow to infinity, canonical NaN; docs/fpu.md).
  *
  * Three stages, each ended by an optional register (cut):
  *  0. unpack, special cases, exponent sum, (manWidth+1)-bit significand product;
  *  1. one-bit normalization, guard and sticky bits;
  *  2. round, overflow/flush, select special results.
  *
  * Latency: the number of cuts present, 3 by default ([[FMul.stages]]). Throughput: one operation
  * per cycle; `out.valid` is `in.valid` delayed by the latency.
  */
class FMul(val fmt: FloatFormat, val cuts: Seq[Boolean] = FMul.defaultCuts) extends Module with PipelineCuts {
  require(cuts.length == FMul.stages, s"FMul has ${FMul.stages} cut points, got ${cuts.length}")
  override def desiredName: String = nameWithCuts(s"FMul_${fmt.name}")

  val io = IO(new Bundle {
    val in = Flipped(Valid(new FOperands(fmt)))
    val out = Valid(UInt(fmt.width.W))
  })

  private val n = fmt.manWidth + 1
  private val expW = fmt.expWidth + 3 // holds 2 - bias .. 2*expMax - bias, signed

  // Stage 0: specials, exponent sum, significand product.
  val v0 = io.in.valid
  val a = FUnpack(fmt, io.in.bits.a)
  val b = FUnpack(fmt, io.in.bits.b)
  val s0 = Wire(new Bundle {
    val special = Bool()
    val specialBits = UInt(fmt.width.W)
    val sign = Bool()
    val exp = SInt(expW.W)
    val prod = UInt((2 * n).W)
  })
  val sign = a.sign ^ b.sign
  val invalid = a.isNaN || b.isNaN || (a.isInf && b.isZero) || (b.isInf && a.isZero)
  s0.special := a.isNaN || b.isNaN || a.isInf || b.isInf || a.isZero || b.isZero
  s0.specialBits := Mux(invalid, FPack.nan(fmt),
    Mux(a.isInf || b.isInf, FPack.inf(fmt, sign), FPack.zero(fmt, sign)))
  s0.sign := sign
  s0.exp := (a.exp +& b.exp).zext - fmt.bias.S
  s0.prod := a.sig * b.sig
  val v1 = validAt(0, v0)
  val r0 = dataAt(0, v0, s0)

  // Stage 1: the product is in [2^(2n-2), 2^(2n)): keep the n-1 fraction bits below its leading one.
  val top = r0.prod(2 * n - 1)
  val s1 = Wire(new Bundle {
    val special = Bool()
    val specialBits = UInt(fmt.width.W)
    val sign = Bool()
    val exp = SInt(expW.W)
    val frac = UInt((n - 1).W)
    val guard = Bool()
    val sticky = Bool()
  })
  s1.special := r0.special
  s1.specialBits := r0.specialBits
  s1.sign := r0.sign
  s1.exp := r0.exp + top.zext
  s1.frac := Mux(top, r0.prod(2 * n - 2, n), r0.prod(2 * n - 3, n - 1))
  s1.guard := Mux(top, r0.prod(n - 1), r0.prod(n - 2))
  val lowSticky = if (n >= 3) r0.prod(n - 3, 0).orR else false.B
  s1.sticky := lowSticky || (top && r0.prod(n - 2))
  val v2 = validAt(1, v1)
  val r1 = dataAt(1, v1, s1)

  // Stage 2: round and pack.
  val rounded = FPack.round(fmt, r1.sign, r1.exp, r1.frac, r1.guard, r1.sticky)
  io.out.valid := validAt(2, v2)
  io.out.bits := dataAt(2, v2, Mux(r1.special, r1.specialBits, rounded))
}

object FMul {
  /** Cut points (optional register stages); the default latency. */
  val stages = 3
  val defaultCuts: Seq[Boolean] = Seq.fill(stages)(true)
}
