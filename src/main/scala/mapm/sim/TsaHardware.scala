package mapm.sim

import java.nio.file.Path
import mapm.MapmError
import mapm.model.{FloatFormat, TsaModel}
import mapm.model.TsaModel.Outcome
import mapm.tsearch.TSA

/** Runs operations through the emitted SystemVerilog of a [[TSA]] in Verilator (through
  * [[VerilatorPipe]]), one operation per cycle, and returns its outputs in operation order.
  *
  * The tag carries each operation's index (modulo 2^32), so a response that comes back out of
  * order, is lost, or arrives after any latency other than the TSA's own is reported as a
  * [[MapmError]] rather than matched to the wrong operation. */
final class TsaHardware(fmt: FloatFormat, cacheDir: Path = VerilatorPipe.defaultCache) {
  private val tagWidth = 32
  /** The latency the design must show (the model's figure). */
  private val latency = TsaModel.latency(fmt)
  private val pipe = VerilatorPipe.build(new TSA(fmt, tagWidth), cacheDir)

  /** Module name of the simulated design. */
  def top: String = pipe.top

  /** Outputs for each (p, h, s) bit-pattern triple, in order. */
  def run(ops: IndexedSeq[(Long, Long, Long)]): IndexedSeq[Outcome] = {
    val (iv, ip, ih, is, it) = (pipe.in("io_in_valid"), pipe.in("io_in_bits_p"), pipe.in("io_in_bits_h"),
      pipe.in("io_in_bits_s"), pipe.in("io_in_bits_tag"))
    val (ov, ol, or, oe, ot) = (pipe.out("io_out_valid"), pipe.out("io_out_bits_tcl"), pipe.out("io_out_bits_tcr"),
      pipe.out("io_out_bits_error"), pipe.out("io_out_bits_tag"))
    val tagMask = (1L << tagWidth) - 1
    val idle = Array.fill(pipe.inputs.length)(BigInt(0))
    val rows = ops.iterator.zipWithIndex.map { case ((p, h, s), i) =>
      val r = new Array[BigInt](pipe.inputs.length)
      r(iv) = 1; r(ip) = p; r(ih) = h; r(is) = s; r(it) = i.toLong & tagMask
      r
    } ++ Iterator.fill(latency)(idle) // drain the pipeline
    val out = new Array[Outcome](ops.length)
    var n = 0
    var cycle = 0L
    pipe.run(rows) { o =>
      if (o(ov) == 1) {
        if (n >= ops.length) MapmError.fail(s"$top produced more responses than operations")
        if (o(ot).toLong != (n.toLong & tagMask) || cycle != n + latency)
          MapmError.fail(s"$top: response ${o(ot)} at cycle $cycle, expected operation $n at cycle ${n + latency}")
        out(n) = Outcome(o(ol) == 1, o(or) == 1, o(oe) == 1)
        n += 1
      }
      cycle += 1
    }
    if (n != ops.length) MapmError.fail(s"$top answered $n of ${ops.length} operations")
    out.toIndexedSeq
  }
}
