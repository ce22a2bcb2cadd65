package mapm.sim

import java.nio.file.Path
import scala.collection.immutable.ArraySeq
import chisel3.{Data, RawModule}
import chisel3.util.Valid

/** Streams operations through a fully pipelined unit with a Valid input and a Valid output, in
  * Verilator (a typed [[VerilatorPipe]] over the two ports, built once per design and cached): one
  * operation or bubble per cycle, then `latency + 1` bubbles to drain the pipeline, handing every
  * valid result to a sink in the order it leaves.
  *
  * The row encoding is the runner's parameter: `encode` gives an operation's values for the
  * input's `bits` leaves in field order, and `decode` makes a result of the output's `bits` leaves
  * (field order) and the cycle it left in (the first streamed cycle is 0).
  */
final class PipeRunner[Op, Res] private (pipe: VerilatorPipe, val latency: Int, encode: Op => Seq[BigInt],
                                         decode: (IndexedSeq[BigInt], Long) => Res) {
  /** Module name of the simulated design. */
  def top: String = pipe.top

  private val zero = BigInt(0)
  private val bubble = Array.fill(pipe.inputs.length)(zero)

  /** Streams `cycles` (Some(op): an operation on a valid cycle, None: a bubble) and calls `sink`
    * with every valid result. */
  def run(cycles: Iterator[Option[Op]])(sink: Res => Unit): Unit = {
    val rows = (cycles ++ Iterator.fill(latency + 1)(None)).map {
      case Some(op) => (BigInt(1) +: encode(op)).toArray
      case None => bubble
    }
    var cycle = -1L
    pipe.run(rows) { o =>
      cycle += 1
      if (o(0) != zero) sink(decode(ArraySeq.unsafeWrapArray(o.tail), cycle))
    }
  }
}

object PipeRunner {
  /** A runner of `gen` on the ports `in` and `out`, whose results leave `latency` cycles after
    * their operations (`encode` and `decode` as in [[PipeRunner]]). */
  def apply[M <: RawModule, Op, Res](gen: => M, latency: Int, cacheDir: Option[Path] = None)(
      in: M => Valid[_ <: Data], out: M => Valid[_ <: Data])(
      encode: Op => Seq[BigInt], decode: (IndexedSeq[BigInt], Long) => Res): PipeRunner[Op, Res] =
    new PipeRunner(VerilatorPipe.of(gen, cacheDir)(in, out), latency, encode, decode)
}
