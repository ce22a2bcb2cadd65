package mapm.tsearch

import chisel3._
import chisel3.util._

/** Pipelined Comparator (3.4.6): decides whether A - B < C for unsigned `width`-bit words A, B,
  * C, one bit per slice from the most significant end, with a register stage after every slice.
  *
  * The inputs arrive skewed, as [[mapm.arith.P2S]] delivers them: slice j (j = 0 first) reads bit
  * width-1-j of a, b and c in the cycle the operation reaches it, i.e. j cycles after the most
  * significant bits were read. Each slice is the logic of Table 3.7 (its carry, a, b, c bits give
  * a new result and done bit) behind the hand-over of Figure 3.20: once `done` is set, later
  * slices pass (done, result) through unchanged. After the last slice, done = 0 means A - B = C
  * or A - B = C + 1 (result 0 or 1), done = 1 means decided, result 1 for A - B > C and 0 for
  * A - B < C (Table 3.5).
  *
  * Latency: `width` cycles from the most significant bits to the outputs (the first slice is
  * combinational from its inputs, every slice ends in a register). Throughput: one comparison
  * per cycle. Registers: 2 per slice (done, result). With `stallable`, an `en` input freezes
  * every slice register while low.
  */
class PipelinedComparator(width: Int, stallable: Boolean = false) extends Module {
  require(width >= 1, s"comparator width must be at least 1, got $width")
  override def desiredName = s"PipelinedComparator_w$width${if (stallable) "_en" else ""}"

  val io = IO(new Bundle {
    /** Minuend A, subtrahend B and compared value C, skewed (bit i valid width-1-i cycles after
      * the most significant bit). */
    val a = Input(UInt(width.W))
    val b = Input(UInt(width.W))
    val c = Input(UInt(width.W))
    val done = Output(Bool())
    val result = Output(Bool())
    /** A - B < C: decided and negative. */
    val less = Output(Bool())
    /** Pipeline enable (stallable comparators only): slice registers hold while it is low. */
    val en = if (stallable) Some(Input(Bool())) else None
  })
  private val enable = io.en.getOrElse(true.B)

  val (done, result) = (0 until width).foldLeft((false.B, false.B)) { case ((doneIn, resultIn), j) =>
    val i = width - 1 - j
    val (r, d) = PipelinedComparator.compLogic(resultIn, io.a(i), io.b(i), io.c(i))
    (RegEnable(doneIn || d, enable).suggestName(s"done_$j"), RegEnable(Mux(doneIn, resultIn, r), enable).suggestName(s"result_$j"))
  }
  io.done := done
  io.result := result
  io.less := done && !result
}

object PipelinedComparator {
  /** Table 3.7, rows in the order of the index (carry, a, b, c): the (result, done) pair. */
  val table: Seq[(Int, Int)] = Seq(
    (0, 0), (0, 1), (0, 1), (0, 1), // carry 0, a 0
    (1, 0), (0, 0), (0, 0), (0, 1), // carry 0, a 1
    (1, 1), (1, 0), (1, 0), (0, 0), // carry 1, a 0
    (1, 1), (1, 1), (1, 1), (1, 0)) // carry 1, a 1

  /** CompLogic of Figure 3.21: (result, done) for one slice. */
  def compLogic(carry: Bool, a: Bool, b: Bool, c: Bool): (Bool, Bool) = {
    val rom = VecInit(table.map { case (r, d) => ((r << 1) | d).U(2.W) })
    val out = rom(Cat(carry, a, b, c))
    (out(1), out(0))
  }
}
