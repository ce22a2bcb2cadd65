package mapm.sim

import java.nio.file.Path
import mapm.MapmError
import mapm.fpu.FpuDepth
import mapm.numerics.{Arith, FloatFormat, TsaModel}
import mapm.numerics.TsaModel.Outcome
import mapm.shader.{SOA, ShaderChain}
import mapm.tsearch.TsaUnit

/** The [[SOA]] in Verilator: [[PipeRunner]]s of `SOA(format, g, tagWidth)` with the row encoding
  * of [[SoaRunner.Op]] and [[SoaRunner.Out]]. */
object SoaRunner {
  /** One operation: kernel, BRDF, h, power r/g/b, contribution r/g/b, query x/y/z, photon x/y/z
    * (bit patterns), and a tag. */
  final case class Op(inputs: Array[Long], tag: Long) {
    require(inputs.length == 15, "an SOA operation has 15 inputs")
  }

  /** One result: the tag, colour bits and flags per channel, cond, and the cycle it was seen in
    * (counting the first streamed cycle as 0). */
  final case class Out(tag: Long, colour: Array[Long], flags: Array[Int], cond: Boolean, cycle: Long)

  /** Builds (or finds cached) the SOA's simulation. */
  def apply(format: FloatFormat, g: Int, tagWidth: Int = 16, arith: Arith = Arith.Online): PipeRunner[Op, Out] =
    PipeRunner(new SOA(format, g, tagWidth, arith = arith), SOA.latency(format, g, FpuDepth.of(format), arith))(_.io.in, _.io.out)(
      op => op.inputs.toSeq.map(BigInt(_)) :+ BigInt(op.tag),
      // colour 0..2, flags 0..2, cond, tag
      (o, cycle) => Out(o(7).toLong, o.slice(0, 3).map(_.toLong).toArray, o.slice(3, 6).map(_.toInt).toArray,
        o(6) != 0, cycle))
}

/** The [[ShaderChain]] in Verilator: [[PipeRunner]]s of `ShaderChain(format, g, tagWidth)` with
  * the row encoding of [[ShaderChainRunner.Op]] and [[ShaderChainRunner.Out]]. */
object ShaderChainRunner {
  /** One operation: kernel, BRDF, h, power r/g/b, contribution r/g/b (bit patterns), a tag. */
  final case class Op(inputs: Array[Long], tag: Long) {
    require(inputs.length == 9, "a shader operation has 9 inputs")
  }

  /** One result: the tag, colour bits and flags per channel, and the cycle it was seen in
    * (counting the first streamed cycle as 0). */
  final case class Out(tag: Long, colour: Array[Long], flags: Array[Int], cycle: Long)

  /** Builds (or finds cached) the chain's simulation. */
  def apply(format: FloatFormat, g: Int, tagWidth: Int = 16): PipeRunner[Op, Out] =
    PipeRunner(new ShaderChain(format, g, tagWidth), ShaderChain.latency(format, g))(_.io.in, _.io.out)(
      op => op.inputs.toSeq.map(BigInt(_)) :+ BigInt(op.tag),
      // colour 0..2, flags 0..2, tag
      (o, cycle) => Out(o(6).toLong, o.slice(0, 3).map(_.toLong).toArray, o.slice(3, 6).map(_.toInt).toArray, cycle))
}

/** The [[TSA]] (or the [[ConvTSA]]) in Verilator: a [[PipeRunner]] of `TSA(fmt, 32)` whose tag carries each
  * operation's index (modulo 2^32), so that [[TsaRunner.run]] reports a response that comes back
  * out of order, is lost, or arrives after any latency other than the model's as a [[MapmError]]
  * rather than matching it to the wrong operation. */
object TsaRunner {
  private val tagWidth = 32
  private val tagMask = (1L << tagWidth) - 1

  /** One response: the outcome, its tag and the cycle it left in. */
  private final case class Out(outcome: Outcome, tag: Long, cycle: Long)

  /** Outputs for each (p, h, s) bit-pattern triple, streamed back to back, in order. */
  def run(fmt: FloatFormat, ops: IndexedSeq[(Long, Long, Long)],
          cacheDir: Option[Path] = None, arith: Arith = Arith.Online): IndexedSeq[Outcome] = {
    val add = FpuDepth.of(fmt).add
    val latency = TsaUnit.latency(fmt, arith, add)
    val runner = PipeRunner(TsaUnit(fmt, tagWidth, stallable = false, arith, add), latency, cacheDir)(_.io.in, _.io.out)(
      (op: (Long, Long, Long, Long)) => Seq(BigInt(op._1), BigInt(op._2), BigInt(op._3), BigInt(op._4)),
      (o, cycle) => Out(Outcome(o(0) == 1, o(1) == 1, o(2) == 1), o(3).toLong, cycle)) // tcl, tcr, error, tag
    val out = new Array[Outcome](ops.length)
    var n = 0
    val top = runner.top
    runner.run(ops.iterator.zipWithIndex.map { case ((p, h, s), i) => Some((p, h, s, i.toLong & tagMask)) }) { o =>
      if (n >= ops.length) MapmError.fail(s"$top produced more responses than operations")
      if (o.tag != (n.toLong & tagMask) || o.cycle != n + latency)
        MapmError.fail(s"$top: response ${o.tag} at cycle ${o.cycle}, expected operation $n at cycle ${n + latency}")
      out(n) = o.outcome
      n += 1
    }
    if (n != ops.length) MapmError.fail(s"$top answered $n of ${ops.length} operations")
    out.toIndexedSeq
  }
}
