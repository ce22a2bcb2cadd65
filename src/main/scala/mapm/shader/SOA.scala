package mapm.shader

import chisel3._
import chisel3.util._
import mapm.fpu.FpuDepth
import mapm.numerics.{Arith, FloatFormat}
import mapm.params.Rgb

/** One shader operation for the [[SOA]]: the photon's kernel, BRDF and power (r, g, b), the
  * query's radius h and contribution (r, g, b), the query position q and the photon position p,
  * all bit patterns of the format, and an opaque tag that leaves with the result. */
class SoaRequest(format: FloatFormat, tagWidth: Int) extends Bundle {
  val kernel = UInt(format.width.W)
  val brdf = UInt(format.width.W)
  val h = UInt(format.width.W)
  val power = Vec(Rgb.Channels, UInt(format.width.W))
  val contrib = Vec(Rgb.Channels, UInt(format.width.W))
  val qx = UInt(format.width.W)
  val qy = UInt(format.width.W)
  val qz = UInt(format.width.W)
  val px = UInt(format.width.W)
  val py = UInt(format.width.W)
  val pz = UInt(format.width.W)
  val tag = UInt(tagWidth.W)
}

/** The result of one shader operation: colour bits and flags (OVF = 1, UNF = 2, INV = 4, as
  * [[ShaderChain]]) per channel, whether the photon lies within h of the query (`cond`), and the
  * operation's tag. The colour is computed whatever `cond` says; the consumer discards it when
  * `cond` is false. */
class SoaResult(format: FloatFormat, tagWidth: Int) extends Bundle {
  val colour = Vec(Rgb.Channels, UInt(format.width.W))
  val flags = Vec(Rgb.Channels, UInt(3.W))
  val cond = Bool()
  val tag = UInt(tagWidth.W)
}

/** The ports of an SOA and of its timing model [[SoaTiming]]. */
class SoaIO(format: FloatFormat, tagWidth: Int) extends Bundle {
  val in = Flipped(Valid(new SoaRequest(format, tagWidth)))
  val out = Valid(new SoaResult(format, tagWidth))
}

/** What a SOM lane instantiates: the [[SOA]], or its timing model [[SoaTiming]]. Both take one
  * operation per cycle and give its result [[latency]] cycles later, never stalling. */
abstract class ShaderUnit extends Module {
  val io: SoaIO
  /** Cycles from an operation on `in` to its result on `out`. */
  val latency: Int
}

/** The shader-operation accelerator (dissertation 3.6): a colour chain (colour_c = ((kernel ·
  * BRDF) / h) · power_c · contribution_c, c = r, g, b) beside the conventional floating-point
  * distance check [[CondCheck]] (|q − p|² < h², rounded as [[mapm.numerics.CondModel]]), both fed by
  * the same operation in the same cycle. The colour chain is the online-arithmetic
  * [[ShaderChain]] with `arith` online (the default), and the conventional [[ConvShaderChain]]
  * with `arith` conventional (the baseline the dissertation compared it with, Table 4.5).
  *
  * The two paths have different latencies; the shorter one's result is delayed by plain
  * registers so that the three colours, their flags, cond and the tag leave in the same cycle.
  * The tag travels through the colour chain; the cond check carries a one-bit dummy tag.
  *
  * With `stageGate` (the default) the colour chain and the cond check clock each register only in
  * the cycles in which it takes an operation's state ([[mapm.util.StageGates]]); the results and
  * their cycles are those of the ungated SOA.
  *
  * The conventional floating-point units (the cond check's, and the conventional chain's) are
  * pipelined to `condDepth` ([[FpuDepth]], by default [[FpuDepth.of]] the format: the depth at
  * which they keep up with the online units' clock).
  *
  * Latency: [[SOA.latency]] = max(ShaderChain N + 18, CondCheck) cycles. At fp32 and fp64 the
  * chain is the longer path (fp32: 42 at g = 0, 45 at g = 3, beside the cond check's 37); at fp16
  * (chain 32 at g = 3, cond check 36), bf16 and smaller formats the cond check is. Conventional:
  * [[ConvShaderChain.latency]] (60 at fp32). Throughput: one operation per cycle, fully pipelined,
  * never stalls;
  * `out.valid` follows `in.valid` and results leave in input order.
  */
class SOA(val format: FloatFormat, val g: Int, val tagWidth: Int = 16,
          val condDepth: Option[FpuDepth] = None, val arith: Arith = Arith.Online,
          val stageGate: Boolean = true) extends ShaderUnit {
  private val depth = condDepth.getOrElse(FpuDepth.of(format))
  override def desiredName: String = SOA.name(format, g, condDepth, arith, stageGate)

  val latency: Int = SOA.latency(format, g, depth, arith)

  val io = IO(new SoaIO(format, tagWidth))
  private val req = io.in.bits

  val chain: ColourChain = Module(arith match {
    case Arith.Online => new ShaderChain(format, g, tagWidth, stageGate)
    case Arith.Conventional => new ConvShaderChain(format, depth, tagWidth, stageGate)
  })
  chain.io.in.valid := io.in.valid
  chain.io.in.bits.kernel := req.kernel
  chain.io.in.bits.brdf := req.brdf
  chain.io.in.bits.h := req.h
  chain.io.in.bits.power := req.power
  chain.io.in.bits.contrib := req.contrib
  chain.io.in.bits.tag := req.tag

  val condCheck = Module(new CondCheck(format, 1, depth, stageGate))
  condCheck.io.in.valid := io.in.valid
  condCheck.io.in.bits.qx := req.qx
  condCheck.io.in.bits.qy := req.qy
  condCheck.io.in.bits.qz := req.qz
  condCheck.io.in.bits.px := req.px
  condCheck.io.in.bits.py := req.py
  condCheck.io.in.bits.pz := req.pz
  condCheck.io.in.bits.h := req.h
  condCheck.io.in.bits.tag := 0.U

  private val chainWait = latency - chain.latency
  private val condWait = latency - condCheck.latency
  // Both paths' valid bits (always equal: the same operations, fixed latencies), so that neither
  // path's valid pipeline is left dangling.
  io.out.valid := ShiftRegister(chain.io.out.valid, chainWait, false.B, true.B) &&
    ShiftRegister(condCheck.io.out.valid, condWait, false.B, true.B)
  io.out.bits.colour := ShiftRegister(chain.io.out.bits.colour, chainWait)
  io.out.bits.flags := ShiftRegister(chain.io.out.bits.flags, chainWait)
  io.out.bits.tag := ShiftRegister(chain.io.out.bits.tag, chainWait)
  io.out.bits.cond := ShiftRegister(condCheck.io.out.bits.cond, condWait)
}

object SOA {
  /** The module name, e.g. `SOA_e8m23_g3` (online) or `ConvSOA_e8m23` (conventional, whose
    * name has no g). A depth of the conventional units other than the format's default adds the
    * stages that matter, e.g. `SOA_e8m23_g3_a4m3c1`, `ConvSOA_e8m23_a4m3c1d20`; an SOA without
    * stage gating ends in `_nsg`. */
  def name(format: FloatFormat, g: Int, condDepth: Option[FpuDepth] = None, arith: Arith = Arith.Online,
           stageGate: Boolean = true): String = {
    val d0 = FpuDepth.of(format)
    val gate = if (stageGate) "" else "_nsg"
    val base = arith match {
      case Arith.Online =>
        s"SOA_${format.name}_g$g" + condDepth.filter(d => (d.add, d.mul, d.cmp) != ((d0.add, d0.mul, d0.cmp)))
          .fold("")(d => s"_a${d.add}m${d.mul}c${d.cmp}")
      case Arith.Conventional =>
        s"ConvSOA_${format.name}" + condDepth.filter(_ != d0).fold("")(d => s"_a${d.add}m${d.mul}c${d.cmp}d${d.div}")
    }
    base + gate
  }

  /** Cycles from input to output: the longer of the colour chain and the cond check. */
  def latency(format: FloatFormat, g: Int, condDepth: FpuDepth, arith: Arith): Int = {
    val chain = arith match {
      case Arith.Online => ShaderChain.latency(format, g)
      case Arith.Conventional => ConvShaderChain.latency(condDepth)
    }
    chain max CondCheck.latency(condDepth)
  }
  def latency(format: FloatFormat, g: Int, condDepth: FpuDepth): Int = latency(format, g, condDepth, Arith.Online)
  def latency(format: FloatFormat, g: Int): Int = latency(format, g, FpuDepth.of(format))
}
