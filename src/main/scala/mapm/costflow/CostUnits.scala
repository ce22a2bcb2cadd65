package mapm.costflow

import mapm.MapmError
import mapm.fpu.{FAdd, FDiv, FMul, FpuDepth}
import mapm.model._
import mapm.numerics._
import mapm.params.NumberParams
import mapm.shader.{CondCheck, SOA, ShaderChain}
import mapm.arith.{OnlineDiv, OnlineMul}
import mapm.tsearch.TsaUnit

/** One operation on a unit's input ports (values in [[CostUnit.inPorts]] order) and the output
  * values the bit-accurate model expects for it (in [[CostUnit.outPorts]] order). */
final case class UnitOp(in: Array[BigInt], expect: Array[BigInt])

/** A unit the cost flow can synthesize, simulate at gate level and check: its generator, its
  * ports, its latency, the operations that drive it and the model's results for them.
  *
  * A unit with a valid input (`validIn`) is a pipeline with a tag that leaves with the result
  * after a fixed latency, in input order; its operations carry the model's expected outputs. A
  * free-running unit (`validIn` empty: the online multiplier and divider, one digit per stage per
  * cycle) takes a row of inputs every cycle and is checked against its RTL alone.
  *
  * @param kind      the `--unit` word
  * @param top       module name of the emitted Verilog
  * @param inPorts   the data inputs an operation sets (for a free-running unit: every input)
  * @param outPorts  the outputs compared (on valid cycles, or every cycle)
  * @param validRate fraction of cycles with an operation, as the unit sees in a 16/16/2 MAPM
  */
final class CostUnit(val kind: String, val top: String, gen: () => chisel3.RawModule, val latency: Int,
                     val inPorts: IndexedSeq[String], val outPorts: IndexedSeq[String], val validRate: Double,
                     val validRateSource: String, val validIn: Option[String] = Some("io_in_valid"),
                     val validOut: Option[String] = Some("io_out_valid")) {
  def module(): chisel3.RawModule = gen()
  /** Whether operations carry the model's outputs (units with a valid input do). */
  def checksModel: Boolean = validIn.isDefined
}

object CostUnits {
  /** The units `cost --unit` knows. */
  val kinds: Seq[String] = Seq("soa", "tsa", "cond", "fadd", "fmul", "fdiv", "mul", "div")

  /** Per-SOA valid rate of the Table 4.8 Cornell frame at 16/16/2 (15.33 SO/cycle over 32 SOAs,
    * docs/mapm.md) and per-TSA rate (14.35 TS ops/cycle over 16 TSAs). */
  val SoaRate = 15.33 / 32
  val TsaRate = 14.35 / 16
  private val rateNote = "16/16/2 Cornell render (docs/mapm.md)"

  private val tagWidth = 16
  private val soaIn = IndexedSeq("kernel", "brdf", "h", "power_0", "power_1", "power_2", "contrib_0", "contrib_1",
    "contrib_2", "qx", "qy", "qz", "px", "py", "pz").map("io_in_bits_" + _) :+ "io_in_bits_tag"

  /** The unit `kind` in `format` with `g` guard digits (the SOA's online units), conventional
    * floating-point units pipelined to `fpuWeight` of logic per stage ([[FpuDepth.of]]), and the
    * SOA and TSA in arithmetic `arith`. */
  def apply(kind: String, format: FloatFormat, g: Int,
            fpuWeight: Double = NumberParams.DefaultFpuStageWeight, arith: Arith = Arith.Online, stageGate: Boolean = true): CostUnit = {
    val depth = FpuDepth.of(format, fpuWeight)
    MapmError.check(arith == Arith.Online || Seq("soa", "tsa").contains(kind),
      s"cost: --arith applies to the soa and tsa units, not '$kind'")
    unit(kind, format, g, depth, arith, stageGate)
  }

  private def unit(kind: String, format: FloatFormat, g: Int, depth: FpuDepth, arith: Arith, stageGate: Boolean): CostUnit = kind match {
    case "soa" =>
      MapmError.check(format.manWidth >= 4 || arith == Arith.Conventional,
        s"cost: the SOA needs at least 4 fraction bits, format $format has ${format.manWidth}")
      new CostUnit("soa", SOA.name(format, g, Some(depth), arith, stageGate), () => new SOA(format, g, tagWidth, Some(depth), arith, stageGate),
        SOA.latency(format, g, depth, arith), soaIn,
        (0 until mapm.params.Rgb.Channels).map(c => s"io_out_bits_colour_$c") ++
          (0 until mapm.params.Rgb.Channels).map(c => s"io_out_bits_flags_$c") ++ Seq("io_out_bits_cond", "io_out_bits_tag"),
        SoaRate, rateNote)
    case "tsa" =>
      new CostUnit("tsa", TsaUnit.name(format, tagWidth, stallable = false, arith, depth.add),
        () => TsaUnit(format, tagWidth, stallable = false, arith, depth.add), TsaUnit.latency(format, arith, depth.add),
        IndexedSeq("io_in_bits_p", "io_in_bits_h", "io_in_bits_s", "io_in_bits_tag"),
        IndexedSeq("io_out_bits_tcl", "io_out_bits_tcr", "io_out_bits_error", "io_out_bits_tag"), TsaRate, rateNote)
    case "cond" =>
      new CostUnit("cond", CondCheck.name(format, tagWidth, depth, stageGate), () => new CondCheck(format, tagWidth, depth, stageGate), CondCheck.latency(depth),
        IndexedSeq("qx", "qy", "qz", "px", "py", "pz", "h", "tag").map("io_in_bits_" + _),
        IndexedSeq("io_out_bits_cond", "io_out_bits_tag"), SoaRate, rateNote + ", as the SOA")
    case "fadd" =>
      new CostUnit("fadd", s"FAdd_${format.name}_s${depth.add}", () => new FAdd(format, depth.add), depth.add,
        IndexedSeq("io_in_bits_a", "io_in_bits_b", "io_in_bits_sub"), IndexedSeq("io_out_bits"), SoaRate, rateNote + ", as the SOA")
    case "fmul" =>
      new CostUnit("fmul", s"FMul_${format.name}_s${depth.mul}", () => new FMul(format, depth.mul), depth.mul,
        IndexedSeq("io_in_bits_a", "io_in_bits_b"), IndexedSeq("io_out_bits"), SoaRate, rateNote + ", as the SOA")
    case "fdiv" =>
      new CostUnit("fdiv", s"FDiv_${format.name}_s${depth.div}", () => new FDiv(format, depth.div), depth.div,
        IndexedSeq("io_in_bits_a", "io_in_bits_b"), IndexedSeq("io_out_bits"), SoaRate, rateNote + ", as the conventional SOA")
    case "mul" | "div" =>
      MapmError.check(format.manWidth >= 4, s"cost: the online units need at least 4 fraction bits, format $format has ${format.manWidth}")
      val n = format.manWidth + 1
      val digits = n + g
      // The SOA's per-channel multipliers (MUL2, MUL3) and its divider, as ShaderChain sizes them.
      val (gen, top, xLen, latency, yName, outName) =
        if (kind == "mul") (() => new OnlineMul(n, digits, digits), s"OnlineMul_n${n}_N${digits}_x$digits", digits, digits + 3, "y", "p")
        else (() => new OnlineDiv(n, digits, digits + 1), s"OnlineDiv_n${n}_N${digits}_x${digits + 1}", digits + 1, digits + 4, "d", "q")
      val xs = (0 until xLen).flatMap(i => Seq(s"io_x_${i}_pos", s"io_x_${i}_neg"))
      new CostUnit(kind, top, gen, latency, xs ++ (0 until n).map(i => s"io_${yName}_$i"),
        (0 until digits).flatMap(i => Seq(s"io_${outName}_${i}_pos", s"io_${outName}_${i}_neg")), 1.0,
        "every cycle (a digit per stage per cycle)", validIn = None, validOut = None)
    case other => MapmError.fail(s"cost: unknown unit '$other' (${kinds.mkString(", ")})")
  }

  /** `n` operations for `u` with the model's results: from the frame's shader and tree-search
    * operations when `frame` is given, else seeded random bit patterns of the format (every
    * value class: zeros, subnormal patterns, infinities, NaNs and normal numbers). */
  def ops(u: CostUnit, format: FloatFormat, g: Int, frame: Option[Frame], n: Int, seed: Long,
          arith: Arith = Arith.Online): IndexedSeq[UnitOp] = {
    val rnd = new scala.util.Random(seed)
    def randomBits(): Long = if (rnd.nextInt(16) == 0) rnd.nextLong() & format.mask
      else { // a normal number near 1 most of the time, so the arithmetic does real work
        val e = math.min(math.max(format.bias + rnd.nextInt(9) - 4, 1), (1 << format.expWidth) - 2).toLong
        (rnd.nextInt(2).toLong << (format.width - 1)) | (e << format.manWidth) | (rnd.nextLong() & ((1L << format.manWidth) - 1))
      }
    if (!u.checksModel) { // each digit 0, +1 or -1 as (pos, neg) pairs; the other inputs random bits
      MapmError.check(frame.isEmpty, s"cost: --unit ${u.kind} takes random digit streams: use --stimulus random")
      return IndexedSeq.fill(n) {
        val row = new Array[BigInt](u.inPorts.length)
        var i = 0
        while (i < row.length) {
          if (u.inPorts(i).endsWith("_pos")) {
            val d = rnd.nextInt(3)
            row(i) = BigInt(if (d == 1) 1 else 0); row(i + 1) = BigInt(if (d == 2) 1 else 0); i += 2
          } else { row(i) = BigInt(rnd.nextInt(2)); i += 1 }
        }
        UnitOp(row, Array.empty)
      }
    }
    val sos: IndexedSeq[FrameOps.So] = if (u.kind == "tsa") IndexedSeq.empty else frame match {
      case Some(f) => FrameOps.shaderOps(f.map, f.querySet, n)
      case None => IndexedSeq.fill(n)(FrameOps.So(Array.fill(15)(randomBits())))
    }
    def b(x: Long): BigInt = BigInt(x) & ((BigInt(1) << 64) - 1) // a port's bits, unsigned (fp64 values fill the Long)
    def bool(x: Boolean): BigInt = if (x) BigInt(1) else BigInt(0)
    val mask = (1 << tagWidth) - 1
    u.kind match {
      case "soa" =>
        val chain = new ShaderChainModel(format, g)
        def colour(so: FrameOps.So, c: Int) = arith match {
          case Arith.Online => chain.colour(so.kernel, so.brdf, so.h, so.power(c), so.contrib(c))
          case Arith.Conventional => ConvChainModel.colour(format, so.kernel, so.brdf, so.h, so.power(c), so.contrib(c))
        }
        sos.zipWithIndex.map { case (so, i) =>
          val res = (0 until 3).map(colour(so, _))
          val cond = CondModel.cond(format, so.q(0), so.q(1), so.q(2), so.p(0), so.p(1), so.p(2), so.h)
          UnitOp((so.inputs.map(b) :+ b(i & mask)).toArray,
            (res.map(r => b(r.bits)) ++ res.map(r => b(r.flags.toLong)) ++ Seq(bool(cond), b(i & mask))).toArray)
        }
      case "cond" =>
        sos.zipWithIndex.map { case (so, i) =>
          val cond = CondModel.cond(format, so.q(0), so.q(1), so.q(2), so.p(0), so.p(1), so.p(2), so.h)
          UnitOp(Array(so.q(0), so.q(1), so.q(2), so.p(0), so.p(1), so.p(2), so.h, (i & mask).toLong).map(b),
            Array(bool(cond), b(i & mask)))
        }
      case "fadd" => // the cond check's first adders: q - p on each axis
        sos.zipWithIndex.map { case (so, i) =>
          val a = so.q(i % 3); val c = so.p(i % 3)
          UnitOp(Array(b(a), b(c), BigInt(1)), Array(b(SoftFloat.sub(format, a, c))))
        }
      case "fmul" => // the cond check's squares of q - p
        sos.zipWithIndex.map { case (so, i) =>
          val d = SoftFloat.sub(format, so.q(i % 3), so.p(i % 3))
          UnitOp(Array(b(d), b(d)), Array(b(SoftFloat.mul(format, d, d))))
        }
      case "fdiv" => // the conventional chain's divider: RN(kernel * BRDF) / h
        sos.map { so =>
          val t1 = SoftFloat.mul(format, so.kernel, so.brdf)
          UnitOp(Array(b(t1), b(so.h)), Array(b(SoftFloat.div(format, t1, so.h))))
        }
      case "tsa" =>
        val ts = frame match {
          case Some(f) => FrameOps.treeSearchOps(f.map, f.querySet, n)
          case None => IndexedSeq.fill(n)(FrameOps.Ts(randomBits(), randomBits() & (format.mask >> 1), randomBits()))
        }
        ts.zipWithIndex.map { case (t, i) =>
          val o = if (arith == Arith.Online) TsaModel.evaluate(format, t.p, t.h, t.s) else ConvTsaModel.evaluate(format, t.p, t.h, t.s)
          UnitOp(Array(b(t.p), b(t.h), b(t.s), b(i & mask)), Array(bool(o.tcl), bool(o.tcr), bool(o.error), b(i & mask)))
        }
    }
  }
}
