package mapm.shader

import mapm.model.FloatFormat
import mapm.sim.VerilatorPipe

/** Runs the emitted SystemVerilog of an [[SOA]] in Verilator (through [[mapm.sim.VerilatorPipe]],
  * built once per design and cached), streaming one shader operation or bubble per cycle and
  * collecting every valid result with the cycle it left in.
  */
final class SoaSim(val format: FloatFormat, val g: Int, val tagWidth: Int = 16) {
  import SoaSim._

  val latency: Int = SOA.latency(format, g)
  private val pipe = VerilatorPipe.build(new SOA(format, g, tagWidth))

  private val inIdx = InputNames.map(n => pipe.in(s"io_in_bits_$n"))
  private val inValid = pipe.in("io_in_valid")
  private val inTag = pipe.in("io_in_bits_tag")
  private val outValid = pipe.out("io_out_valid")
  private val outTag = pipe.out("io_out_bits_tag")
  private val outCond = pipe.out("io_out_bits_cond")
  private val outColour = (0 until 3).map(c => pipe.out(s"io_out_bits_colour_$c"))
  private val outFlags = (0 until 3).map(c => pipe.out(s"io_out_bits_flags_$c"))
  private val zero = BigInt(0)

  /** Streams `cycles` (Some(op) = an operation on a valid cycle, None = a bubble), then enough
    * bubbles to drain the pipeline, and calls `sink` with every valid result in order. */
  def run(cycles: Iterator[Option[Op]])(sink: Out => Unit): Unit = {
    val rows = (cycles ++ Iterator.fill(latency + 1)(None)).map { c =>
      val row = Array.fill(pipe.inputs.length)(zero)
      c.foreach { op =>
        row(inValid) = BigInt(1)
        row(inTag) = BigInt(op.tag)
        for (i <- InputNames.indices) row(inIdx(i)) = BigInt(op.inputs(i))
      }
      row
    }
    var cycle = -1L
    pipe.run(rows) { o =>
      cycle += 1
      if (o(outValid) != zero)
        sink(Out(o(outTag).toLong, outColour.map(o(_).toLong).toArray, outFlags.map(o(_).toInt).toArray,
          o(outCond) != zero, cycle))
    }
  }
}

object SoaSim {
  /** The data inputs of an operation, in [[Op.inputs]] order (port `io_in_bits_<name>`). */
  val InputNames: IndexedSeq[String] = IndexedSeq("kernel", "brdf", "h", "power_0", "power_1", "power_2",
    "contrib_0", "contrib_1", "contrib_2", "qx", "qy", "qz", "px", "py", "pz")

  /** One operation: kernel, BRDF, h, power r/g/b, contribution r/g/b, query x/y/z, photon x/y/z
    * (bit patterns), and a tag. */
  final case class Op(inputs: Array[Long], tag: Long) {
    require(inputs.length == InputNames.length, s"a shader operation has ${InputNames.length} inputs")
  }

  /** One result: the tag, colour bits and flags per channel, cond, and the cycle it was seen in
    * (counting the first streamed cycle as 0). */
  final case class Out(tag: Long, colour: Array[Long], flags: Array[Int], cond: Boolean, cycle: Long)
}
