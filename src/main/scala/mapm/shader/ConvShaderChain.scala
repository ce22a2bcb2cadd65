package mapm.shader

import chisel3._
import chisel3.util._
import chisel3.experimental.hierarchy.{Definition, Instance}
import mapm.fpu.{FDiv, FMul, FOperands, FloatFields, FpuDepth}
import mapm.numerics.FloatFormat
import mapm.params.Rgb
import mapm.util.StageGates

/** The conventional colour chain, the baseline of dissertation Table 4.5: per channel
  * colour_c = RN(RN(RN(RN(kernel · BRDF) / h) · power_c) · contribution_c), every operation an
  * IEEE-754 operation of the format rounded to nearest even, bit for bit
  * [[mapm.numerics.ConvChainModel]] (../shared/vectors/conventional). Seven pipelined multipliers
  * ([[FMul]]) and one divider ([[FDiv]]): MUL1 and the divider are shared by the channels, MUL2
  * and MUL3 are one per channel.
  *
  * The special cases (shader-chain.md section 2, rules 1 and 2) are decided from the inputs in
  * the first cycle and travel beside the units. After the last multiplier one cycle applies them
  * and the output rule: every input normal, an intermediate that overflowed has made the product
  * an infinity (largest finite value and OVF), one that underflowed has made it a zero (+0 and
  * UNF), as the model argues.
  *
  * With `gated` (the default), every data register is clocked only in the cycles in which it
  * takes an operation's state ([[mapm.util.StageGates]]), as in the online chain.
  *
  * Latency: [[ConvShaderChain.latency]] = mul + div + mul + mul + 1 cycles of `depth` (60 at fp32
  * with the default depth). Throughput: one operation per cycle, fully pipelined, never stalls;
  * `out.valid` follows `in.valid` and tags leave in order.
  */
class ConvShaderChain(val format: FloatFormat, val depth: FpuDepth, val tagWidth: Int = 16, val gated: Boolean = true)
    extends ColourChain {
  require(tagWidth >= 1, s"ConvShaderChain: tag width must be at least 1, got $tagWidth")
  override def desiredName: String = ConvShaderChain.name(format, depth, gated)

  val latency: Int = ConvShaderChain.latency(depth)
  val io = IO(new ColourChainIO(format, tagWidth))

  private val req = io.in.bits
  private val f = FloatFields(format)

  private def operands(u: Valid[FOperands], valid: Bool, a: UInt, b: UInt): Unit = {
    u.valid := valid; u.bits.a := a; u.bits.b := b
  }
  // Depth d: the cycle d after the operation's on `in` (see StageGates); each unit takes its
  // operands at depth `at`.
  private val stages = new StageGates(io.in.valid, gated)
  private lazy val mulDef = Definition(new FMul(format, depth.mul, gated)) // elaborated once, instantiated seven times
  private def mul(valid: Bool, a: UInt, b: UInt, at: Int): Valid[UInt] = {
    val u = Instance(mulDef); stages.connect(u.io.clocks, at); operands(u.io.in, valid, a, b); u.io.out
  }
  private def div(valid: Bool, a: UInt, b: UInt, at: Int): Valid[UInt] = {
    val u = Module(new FDiv(format, depth.div, gated)); stages.connect(u.io.clocks, at); operands(u.io.in, valid, a, b); u.io.out
  }

  // MUL1 and the divider, shared by the channels.
  private val t1 = mul(io.in.valid, req.kernel, req.brdf, 0)
  private val t2 = div(t1.valid, t1.bits, stages.delay(req.h, depth.mul, 0), depth.mul)
  private val toMul2 = depth.mul + depth.div
  private val toMul3 = toMul2 + depth.mul

  // Rules 1 and 2 per channel, from the inputs: quiet NaN (INV), or +0 with UNF when a zero
  // factor was a subnormal pattern.
  private val anyInfNaN = (Seq(req.kernel, req.brdf, req.h) ++ req.power ++ req.contrib).map(f.isInfOrNaN).reduce(_ || _)
  private val invalid = anyInfNaN || f.isZero(req.h)
  private val zeroShared = f.isZero(req.kernel) || f.isZero(req.brdf)
  private val flushedShared = f.isFlushed(req.kernel) || f.isFlushed(req.brdf)

  private class Special extends Bundle {
    val invalid = Bool()
    val zero = Bool()
    val flushed = Bool()
  }
  private val special = VecInit((0 until Rgb.Channels).map { c =>
    val s = Wire(new Special)
    s.invalid := invalid
    s.zero := zeroShared || f.isZero(req.power(c)) || f.isZero(req.contrib(c))
    s.flushed := flushedShared || f.isFlushed(req.power(c)) || f.isFlushed(req.contrib(c))
    s
  })
  // Registered once before its delay: the classes' logic over every operand is a path of its own.
  private val specialLate = stages.delay(stages.reg(special, 0), latency - 2, 1)

  // MUL2 and MUL3 per channel, then the output rule (one registered cycle).
  private val t4 = (0 until Rgb.Channels).map { c =>
    val t3 = mul(t2.valid, t2.bits, stages.delay(req.power(c), toMul2, 0), toMul2)
    mul(t3.valid, t3.bits, stages.delay(req.contrib(c), toMul3, 0), toMul3)
  }
  private val colour = Wire(Vec(Rgb.Channels, UInt(format.width.W)))
  private val flags = Wire(Vec(Rgb.Channels, UInt(3.W)))
  for (c <- 0 until Rgb.Channels) {
    val x = t4(c).bits
    val sp = specialLate(c)
    val overflow = f.isInfOrNaN(x)
    val underflow = f.isZero(x)
    val maxFinite = Cat(f.sign(x), (format.expMax - 1).U(format.expWidth.W), Fill(format.manWidth, 1.U(1.W)))
    colour(c) := Mux(sp.invalid, format.quietNaN.U(format.width.W),
      Mux(sp.zero || underflow, 0.U, Mux(overflow, maxFinite, x)))
    flags(c) := Mux(sp.invalid, ConvShaderChain.Inv.U,
      Mux(sp.zero, Mux(sp.flushed, ConvShaderChain.Unf.U, 0.U),
        Mux(overflow, ConvShaderChain.Ovf.U, Mux(underflow, ConvShaderChain.Unf.U, 0.U))))
  }
  io.out.valid := RegNext(t4.map(_.valid).reduce(_ && _), false.B)
  io.out.bits.colour := stages.reg(colour, latency - 1)
  io.out.bits.flags := stages.reg(flags, latency - 1)
  io.out.bits.tag := stages.delay(req.tag, latency, 0)
}

object ConvShaderChain {
  private val Ovf = 1
  private val Unf = 2
  private val Inv = 4

  /** The module name, e.g. `ConvShaderChain_e8m23_m9d32` (stage-gated; `_nsg` ungated). */
  def name(format: FloatFormat, depth: FpuDepth, gated: Boolean = true): String =
    s"ConvShaderChain_${format.name}_m${depth.mul}d${depth.div}${if (gated) "" else "_nsg"}"

  /** Cycles from input to output: MUL1, the divider, MUL2, MUL3, then the output rule. */
  def latency(depth: FpuDepth): Int = 3 * depth.mul + depth.div + 1
}
