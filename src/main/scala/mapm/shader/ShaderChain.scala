package mapm.shader

import mapm.arith._

import chisel3._
import chisel3.util._
import mapm.arith.P2S
import mapm.fpu.FloatFields
import mapm.numerics.FloatFormat
import mapm.params.Rgb
import mapm.util.StageGates

/** One shader operation: the shared kernel, BRDF and h, and per colour channel (r, g, b) the
  * photon power and the contribution, as bit patterns of the format, with an opaque tag. */
class ShaderRequest(format: FloatFormat, tagWidth: Int) extends Bundle {
  val kernel = UInt(format.width.W)
  val brdf = UInt(format.width.W)
  val h = UInt(format.width.W)
  val power = Vec(Rgb.Channels, UInt(format.width.W))
  val contrib = Vec(Rgb.Channels, UInt(format.width.W))
  val tag = UInt(tagWidth.W)
}

/** The colour of one shader operation: bits and flags (OVF = 1, UNF = 2, INV = 4) per channel,
  * and the operation's tag. */
class ShaderResult(format: FloatFormat, tagWidth: Int) extends Bundle {
  val colour = Vec(Rgb.Channels, UInt(format.width.W))
  val flags = Vec(Rgb.Channels, UInt(3.W))
  val tag = UInt(tagWidth.W)
}

/** A colour chain's ports: one shader operation in, its colours, flags and tag out. */
class ColourChainIO(format: FloatFormat, tagWidth: Int) extends Bundle {
  val in = Flipped(Valid(new ShaderRequest(format, tagWidth)))
  val out = Valid(new ShaderResult(format, tagWidth))
}

/** The colour part of an SOA, online ([[ShaderChain]]) or conventional ([[ConvShaderChain]]): a
  * fixed-latency pipeline, one operation per cycle, results in input order. */
abstract class ColourChain extends Module {
  val io: ColourChainIO
  /** Cycles from an operation on `in` to its result on `out`. */
  val latency: Int
}

/** The colour part of the shader-operation accelerator (dissertation 3.6, shader-chain.md):
  * colour_c = ((kernel · BRDF) / h) · power_c · contribution_c for c = r, g, b, digit-serial in
  * online arithmetic with N = n + g digits per unit. The three channels share MUL1 (kernel ·
  * BRDF), the divider (/ h) and QN, and leave in the same cycle.
  *
  * Datapath (timing of shader-chain.md §6, cycle 1 = the cycle the operation is on `in`):
  * P2S skews the significands (kernel/BRDF bit s in cycle s, h in s+3, power s+10, contribution
  * s+14); MUL1 (cycles 1 … N+3), DIV (4 … N+7), QN (10 … N+9), per channel MUL2 (11 … N+13) and
  * MUL3 (15 … N+17), then normalization and packing in cycle N+18. The exponent adder tree and
  * the special-case classes are formed in cycles 1 and 2 and travel beside the significands.
  *
  * With `gated` (the default), every register is clocked only in the cycles in which it takes an
  * operation's state ([[mapm.util.StageGates]]: one clock gate per cycle of the chain, shared by
  * the units' registers of that cycle); the results and their cycles are those of the ungated
  * chain.
  *
  * Latency: [[latency]] = N + 18 cycles from `in` to `out` (42 for fp32 with g = 0, 45 with
  * g = 3). Throughput: one operation per cycle, fully pipelined, never stalls; `out.valid`
  * follows `in.valid` and tags leave in order.
  */
class ShaderChain(val format: FloatFormat, val g: Int, val tagWidth: Int = 16, val gated: Boolean = true) extends ColourChain {
  private val n = format.manWidth + 1
  private val ew = format.expWidth
  require(g >= 0 && g <= 8 && n >= 5 && tagWidth >= 1, s"ShaderChain: format $format, g = $g, tag width $tagWidth")
  override def desiredName = ShaderChain.name(format, g, gated)

  /** Digits per online unit. */
  val digits: Int = n + g
  /** Cycles from an operation on `in` to its result on `out`. */
  val latency: Int = ShaderChain.latency(format, g)

  val io = IO(new ColourChainIO(format, tagWidth))

  private val req = io.in.bits
  private val f = FloatFields(format)
  // Depth d = cycle d + 1 of the timing above (the operation is on `in` at depth 0).
  private val stages = new StageGates(io.in.valid, gated)

  /** The n significand bits 1.f of `x`, skewed by P2S after `delay` cycles: bit s (MSB = 1)
    * comes out in cycle s + delay. */
  private def serial(x: UInt, delay: Int): Vec[Bool] = {
    val p2s = Module(new P2S(n, gated = gated))
    p2s.io.in := stages.delay(Cat(1.U(1.W), f.frac(x)), delay, 0)
    stages.connect(p2s.io.clocks, delay)
    VecInit((1 to n).map(s => p2s.io.out(n - s)))
  }

  // Significand datapath, shared part: MUL1 = kernel × BRDF, DIV = (0, p1) / h, QN.
  val mul1 = Module(new OnlineMul(n, digits, n, gated))
  stages.connect(mul1.io.clocks, 0)
  mul1.io.x := VecInit(serial(req.kernel, 0).map(b => SignedDigit(b, false.B)))
  mul1.io.y := serial(req.brdf, 0)

  val div = Module(new OnlineDiv(n, digits, digits + 1, gated))
  stages.connect(div.io.clocks, 3)
  div.io.x := VecInit(SignedDigit.zero +: mul1.io.p)
  div.io.d := serial(req.h, 3)

  val qn = Module(new QuasiNormalize(digits, gated))
  stages.connect(qn.io.clocks, 8)
  qn.io.q := div.io.q

  // Exponents and special cases, formed in cycle 1.
  val exps = Module(new ExponentPath(ew, Rgb.Channels, gated))
  stages.connect(exps.io.clocks, 0)
  exps.io.kernel := f.exp(req.kernel)
  exps.io.brdf := f.exp(req.brdf)
  exps.io.h := f.exp(req.h)
  exps.io.power := VecInit(req.power.map(f.exp))
  exps.io.contrib := VecInit(req.contrib.map(f.exp))

  private val toPack = digits + 17 // from cycle 1 to the packing cycle N+18
  private val sAtPack = stages.shift(qn.io.s, digits + 7, 10) // s appears in cycle 11

  // What rides beside the significands to the packing cycle, per channel: E_0 (from cycle 2), the
  // result's sign and the special cases (registered once to join it); and the tag, one cycle
  // further. One delay for them all.
  private class Side extends Bundle {
    val e0 = SInt((ew + 3).W)
    val sign = Bool()
    val special = new ShaderSpecial
  }
  private class Beside extends Bundle {
    val channels = Vec(Rgb.Channels, new Side)
    val tag = UInt(tagWidth.W)
  }
  private val beside0 = Wire(new Beside)
  beside0.tag := req.tag
  for (c <- 0 until Rgb.Channels) {
    val factors = Seq(req.kernel, req.brdf, req.power(c), req.contrib(c))
    beside0.channels(c).e0 := DontCare
    beside0.channels(c).sign := (factors :+ req.h).map(f.sign).reduce(_ ^ _)
    beside0.channels(c).special.inv := (factors :+ req.h).map(f.isInfOrNaN).reduce(_ || _) || f.isZero(req.h)
    beside0.channels(c).special.zero := factors.map(f.isZero).reduce(_ || _)
    beside0.channels(c).special.flushed := factors.map(f.isFlushed).reduce(_ || _)
  }
  private val beside = WireInit(stages.reg(beside0, 0))
  for (c <- 0 until Rgb.Channels) beside.channels(c).e0 := exps.io.e0(c)
  private val sideAtPack = stages.delay(beside, toPack - 1, 1)
  private def side(c: Int): Side = sideAtPack.channels(c)

  val result = Wire(new ShaderResult(format, tagWidth))
  for (c <- 0 until Rgb.Channels) {
    val (power, contrib) = (req.power(c), req.contrib(c))
    val mul2 = Module(new OnlineMul(n, digits, digits, gated))
    stages.connect(mul2.io.clocks, 10)
    mul2.io.x := qn.io.out
    mul2.io.y := serial(power, 10)
    val mul3 = Module(new OnlineMul(n, digits, digits, gated))
    stages.connect(mul3.io.clocks, 14)
    mul3.io.x := mul2.io.p
    mul3.io.y := serial(contrib, 14)

    val pack = Module(new NormalizePack(format, digits, gated))
    stages.connect(pack.io.clocks, 18)
    pack.io.digits := mul3.io.p
    pack.io.e0 := side(c).e0
    pack.io.s := sAtPack
    pack.io.sign := side(c).sign
    pack.io.special := side(c).special
    result.colour(c) := pack.io.bits
    result.flags(c) := pack.io.flags
  }
  result.tag := stages.reg(sideAtPack.tag, toPack)

  io.out.valid := stages.valid(latency)
  io.out.bits := result
}

object ShaderChain {
  /** The module name, e.g. `ShaderChain_e8m23_g3` (stage-gated; `_nsg` ungated). */
  def name(format: FloatFormat, g: Int, gated: Boolean = true): String =
    s"ShaderChain_${format.name}_g$g${if (gated) "" else "_nsg"}"

  /** Cycles from input to output: the last MUL3 digit in cycle N+17, packing in N+18. */
  def latency(format: FloatFormat, g: Int): Int = format.manWidth + 1 + g + 18

  /** Per-unit latencies in cycles (stages), for the documentation and the emit report. */
  def unitLatencies(format: FloatFormat, g: Int): Seq[(String, Int)] = {
    val nd = format.manWidth + 1 + g
    Seq("MUL1/MUL2/MUL3 (N+3 stages each)" -> (nd + 3), "DIV (N+4 stages)" -> (nd + 4),
      "QN" -> 1, "normalize + pack" -> 1, "whole chain" -> latency(format, g))
  }
}
