package mapm.shader

import chisel3._
import chisel3.util._
import chisel3.experimental.hierarchy.{Definition, Instance}
import mapm.fpu.{FAdd, FCmpLt, FMul, FpuDepth}
import mapm.numerics.FloatFormat
import mapm.util.{StageClocks, StageGates}

/** Inputs of [[CondCheck]]: query point q, photon position p, kernel radius h (bit patterns of
  * the format) and an opaque tag that leaves with the result. */
class CondIn(fmt: FloatFormat, tagWidth: Int) extends Bundle {
  val qx = UInt(fmt.width.W)
  val qy = UInt(fmt.width.W)
  val qz = UInt(fmt.width.W)
  val px = UInt(fmt.width.W)
  val py = UInt(fmt.width.W)
  val pz = UInt(fmt.width.W)
  val h = UInt(fmt.width.W)
  val tag = UInt(tagWidth.W)
}

/** Result of [[CondCheck]]: whether the photon is inside the radius, and the input's tag. */
class CondOut(tagWidth: Int) extends Bundle {
  val cond = Bool()
  val tag = UInt(tagWidth.W)
}

/** The shader operation's distance condition (3.6.1) from conventional pipelined floating-point
  * units: cond = |q - p|^2 < h^2, each operation rounded to nearest even in `fmt`, in exactly the
  * order of [[mapm.numerics.CondModel]], with which it is bit-exact:
  * {{{
  *   dx = qx - px;  dy = qy - py;  dz = qz - pz        3 FAdd (subtract)
  *   dx*dx, dy*dy, dz*dz, hh = h*h                     4 FMul (squarers)
  *   xy = dx*dx + dy*dy                                FAdd
  *   d2 = xy + dz*dz                                   FAdd
  *   cond = d2 < hh                                    FCmpLt
  * }}}
  * h waits one adder latency, dz*dz one and hh two, in valid-gated delay registers; the tag
  * travels in such registers beside the units.
  *
  * The units' pipeline depth is `depth` ([[FpuDepth]]; by default pipelined for the clock the
  * online units reach, docs/cost.md). With `gated` every data register, the units' included, is
  * clocked only in the cycles in which it takes an operation's state ([[mapm.util.StageGates]]).
  *
  * Latency: [[latency]] = 3 FAdd + FMul + FCmpLt latencies (37 cycles at fp32, 36 at fp16 by
  * default). Throughput: one check per cycle; results leave in input order with their tags.
  */
class CondCheck(val fmt: FloatFormat, val tagWidth: Int, val depth: FpuDepth, val gated: Boolean) extends Module {
  def this(fmt: FloatFormat, tagWidth: Int, depth: FpuDepth) = this(fmt, tagWidth, depth, false)
  def this(fmt: FloatFormat, tagWidth: Int) = this(fmt, tagWidth, FpuDepth.of(fmt))
  require(tagWidth >= 1, s"CondCheck tag width must be at least 1, got $tagWidth")
  override def desiredName: String = CondCheck.name(fmt, tagWidth, depth, gated)

  val latency: Int = CondCheck.latency(depth)

  val io = IO(new Bundle {
    val in = Flipped(Valid(new CondIn(fmt, tagWidth)))
    val out = Valid(new CondOut(tagWidth))
  })

  // Depth d: the cycle d after the operation's on `in` (see StageGates).
  private val stages = new StageGates(io.in.valid, gated)

  /** a + b (or a - b) in an [[FAdd]] that takes the operands at depth `at`; the operands' valid
    * bits always agree and are ANDed. */
  // The adders and multipliers are elaborated once each and instantiated.
  private lazy val addDef = Definition(new FAdd(fmt, depth.add, gated = gated))
  // Every product here is a square: squarers (half the partial products) where the depth allows.
  private lazy val mulDef = Definition(new FMul(fmt, depth.mul, gated, square = FMul.squareFits(fmt, depth.mul)))
  private def add(a: Valid[UInt], b: Valid[UInt], sub: Boolean, at: Int): Valid[UInt] = {
    val u = Instance(addDef)
    stages.connect(u.io.clocks, at)
    u.io.in.valid := a.valid && b.valid
    u.io.in.bits.a := a.bits
    u.io.in.bits.b := b.bits
    u.io.in.bits.sub := sub.B
    u.io.out
  }
  private def square(x: Valid[UInt], at: Int): Valid[UInt] = {
    val u = Instance(mulDef)
    stages.connect(u.io.clocks, at)
    u.io.in.valid := x.valid
    u.io.in.bits.a := x.bits
    u.io.in.bits.b := x.bits
    u.io.out
  }
  /** `x`, at depth `at`, delayed by `cycles` registers that load only while the valid bit beside
    * them is set (gated: clocked only then, or a ring, [[StageGates.delay]]). */
  private def delay[T <: Data](x: Valid[T], cycles: Int, at: Int): Valid[T] =
    if (gated) {
      val r = Wire(Valid(chiselTypeOf(x.bits)))
      // x.valid is depth at's valid bit, which StageGates' chain already carries on.
      assert(x.valid === stages.valid(at), "cond check: a delayed value's valid bit is not its depth's")
      r.valid := stages.valid(at + cycles)
      r.bits := stages.delay(x.bits, cycles, at)
      r
    } else (0 until cycles).foldLeft(x) { (d, _) =>
      val r = Wire(Valid(chiselTypeOf(d.bits)))
      r.valid := RegNext(d.valid, false.B)
      r.bits := RegEnable(d.bits, d.valid)
      r
    }
  private def input[T <: Data](x: T): Valid[T] = {
    val v = Wire(Valid(chiselTypeOf(x)))
    v.valid := io.in.valid
    v.bits := x
    v
  }

  val in = io.in.bits
  val addLatency: Int = depth.add
  private val (a, m) = (depth.add, depth.mul)
  val dx = add(input(in.qx), input(in.px), sub = true, 0)
  val dy = add(input(in.qy), input(in.py), sub = true, 0)
  val dz = add(input(in.qz), input(in.pz), sub = true, 0)
  val xy = add(square(dx, a), square(dy, a), sub = false, a + m)
  val d2 = add(xy, delay(square(dz, a), a, a + m), sub = false, 2 * a + m)
  val hh = delay(square(delay(input(in.h), a, 0), a), 2 * a, a + m)

  val cmp = Module(new FCmpLt(fmt, depth.cmp, gated))
  stages.connect(cmp.io.clocks, 3 * a + m)
  cmp.io.in.valid := d2.valid && hh.valid
  cmp.io.in.bits.a := d2.bits
  cmp.io.in.bits.b := hh.bits

  io.out.valid := cmp.io.out.valid
  io.out.bits.cond := cmp.io.out.bits
  io.out.bits.tag := delay(input(in.tag), latency, 0).bits
}

object CondCheck {
  /** The module name, e.g. `CondCheck_e8m23_t16_a8m9c1` (the units' stages; `_sg` stage-gated). */
  def name(fmt: FloatFormat, tagWidth: Int, depth: FpuDepth, gated: Boolean = false): String =
    s"CondCheck_${fmt.name}_t${tagWidth}_a${depth.add}m${depth.mul}c${depth.cmp}${StageClocks.suffix(gated)}"

  /** Cycles from input to output at the units' depth. */
  def latency(depth: FpuDepth): Int = 3 * depth.add + depth.mul + depth.cmp
}
