package mapm.soc

import chisel3._
import chisel3.util._
import mapm.numerics.{FloatFormat, FrameAccum}

/** One colour channel into the frame accumulator's fixed point ([[FrameAccum.convert]], bit for
  * bit): c * 2^-scale rounded to nearest even, as a two's-complement number of `limitBits + 1`
  * bits, with the faults that refuse it (`nonFinite`: an infinity or NaN; `range`: a magnitude of
  * 2^limitBits or more). Exponent field 0 is zero. Combinational.
  *
  * The significand (m + 1 bits) moves left by the exponent less the scale, or right with its
  * round and sticky bits; a right shift of m + 3 or more leaves less than a quarter, which rounds
  * to 0, so the shift is capped there.
  */
class FrameConvert(val accum: FrameAccum) extends Module {
  private val f = accum.format
  private val m = f.manWidth
  private val lim = accum.limitBits
  require(lim >= m + 2, s"the frame accumulator's limit of $lim bits must exceed the ${m + 1}-bit significand by one: widen the sums or narrow the count")
  override def desiredName = s"FrameConvert_${f.name}_a${accum.accBits}c${accum.countBits}"

  val io = IO(new Bundle {
    val in = Input(UInt(f.width.W))
    val scale = Input(SInt(FrameArith.ScaleBits.W))
    val out = Output(SInt((lim + 1).W))
    val nonFinite = Output(Bool())
    val range = Output(Bool())
  })

  private val e = io.in(m + f.expWidth - 1, m)
  private val sig = Cat(1.U(1.W), io.in(m - 1, 0))
  private val neg = io.in(f.width - 1)
  // shift = e - bias - m - scale, wide enough for every exponent and scale.
  private val sh = e.zext - (f.bias + m).S - io.scale
  private val left = sh >= 0.S
  private val tooBig = left && sh >= (lim - m).S
  private val lsh = sh.asUInt(log2Ceil(lim) - 1, 0)
  private val lval = (sig << lsh)(lim - 1, 0)
  private val k = (-sh).asUInt
  private val cap = m + 3
  private val kk = Mux(k >= cap.U, cap.U, k(log2Ceil(cap + 1) - 1, 0))
  private val full = Cat(sig, 0.U(cap.W)) >> kk
  private val q = full >> cap
  private val rem = full(cap - 1, 0)
  private val up = rem(cap - 1) && (rem(cap - 2, 0).orR || q(0))
  private val rval = (q +& up.asUInt).pad(lim)
  private val mag = Mux(e === 0.U, 0.U, Mux(left, lval, rval))
  io.out := Mux(neg, -(mag.zext), mag.zext)
  io.nonFinite := e === f.expMax.U
  io.range := e =/= f.expMax.U && e =/= 0.U && tooBig
}

/** A frame accumulator sum rounded once to the format ([[FrameAccum.resolve]], bit for bit):
  * sum * 2^scale to nearest even, a result below the smallest normal a zero of its sign, above the
  * largest finite value infinity, a zero sum +0. Combinational: a leading-zero count, a
  * normalizing shift and the rounding.
  */
class FrameResolve(val accum: FrameAccum) extends Module {
  private val f = accum.format
  private val n = f.manWidth + 1
  private val a = accum.accBits
  require(a > n, s"the frame accumulator's $a-bit sums must be wider than the ${n}-bit significand")
  override def desiredName = s"FrameResolve_${f.name}_a$a"

  val io = IO(new Bundle {
    val sum = Input(SInt(a.W))
    val scale = Input(SInt(FrameArith.ScaleBits.W))
    val out = Output(UInt(f.width.W))
  })

  private val neg = io.sum < 0.S
  private val mag = Mux(neg, (-io.sum).asUInt, io.sum.asUInt)(a - 1, 0)
  private val lz = PriorityEncoder(Reverse(mag))
  private val norm = (mag << lz)(a - 1, 0)
  private val kept = norm(a - 1, a - n)
  private val rest = norm(a - n - 1, 0)
  private val up = rest(a - n - 1) && ((if (a - n >= 2) rest(a - n - 2, 0).orR else false.B) || kept(0))
  private val rounded = kept +& up.asUInt
  private val carry = rounded(n)
  private val frac = Mux(carry, 0.U, rounded(n - 2, 0))
  // Unbiased exponent of the leading bit: its position (a - 1 - lz) plus the scale, plus the carry.
  private val e = (a - 1).S - lz.zext + io.scale + carry.zext
  private val sign = neg.asUInt
  io.out := Mux(mag === 0.U, 0.U,
    Mux(e > f.maxExp.S, Cat(sign, f.expMax.U(f.expWidth.W), 0.U(f.manWidth.W)),
      Mux(e < f.minExp.S, Cat(sign, 0.U((f.width - 1).W)),
        Cat(sign, (e + f.bias.S).asUInt(f.expWidth - 1, 0), frac))))
}

object FrameArith {
  /** Width of the FRAME_SCALE register's value as the datapath takes it (two's complement). */
  val ScaleBits: Int = 16
}
