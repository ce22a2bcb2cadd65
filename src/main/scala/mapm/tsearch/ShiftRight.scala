package mapm.tsearch

import chisel3._
import chisel3.util._

/** Shift Right (3.4.4): a barrel shifter that aligns a significand by the distance that
  * [[ShiftAmountLogic]] hands over, with a sticky output for the bits it drops.
  *
  * The amount `si` is (amountWidth)-bit two's complement in the negative form: when its sign bit
  * is 0 the distance is `si`; when it is 1 the distance is -si, realised as sd = ~si (which is
  * -si - 1) through the ordinary levels plus an additional final level that shifts by one more.
  * Levels shift by 2^i for i < log2Ceil(width); a distance with a higher bit set shifts
  * everything out, and so does any distance of `width` or more: the output is then zero.
  * Zeros are shifted in. `sticky` is the OR of every bit shifted out (it lets the TSA keep the
  * comparison exact; see `mapm.model.TsaModel`).
  *
  * Combinational (no latency).
  */
class ShiftRight(width: Int, amountWidth: Int) extends RawModule {
  require(width >= 1, s"shifter width must be at least 1, got $width")
  require(amountWidth >= 2, s"amount width must be at least 2 (sign and one bit), got $amountWidth")
  override def desiredName = s"ShiftRight_w${width}_a$amountWidth"

  val io = IO(new Bundle {
    val din = Input(UInt(width.W))
    /** Shift amount, negative form (see above). */
    val si = Input(UInt(amountWidth.W))
    val dout = Output(UInt(width.W))
    /** Some 1 bit of din was shifted out. */
    val sticky = Output(Bool())
  })

  val additionalShift = io.si(amountWidth - 1)
  val magnitude = io.si(amountWidth - 2, 0)
  val sd = Mux(additionalShift, ~magnitude, magnitude)

  /** Levels that shift by less than the width; any higher bit of sd clears the word. */
  val levels = math.min(log2Ceil(width), amountWidth - 1)
  val (shifted, lostInLevels) = (0 until levels).foldLeft((io.din, false.B)) { case ((v, lost), i) =>
    val k = 1 << i
    (Mux(sd(i), v >> k, v), lost || (sd(i) && v(k - 1, 0).orR))
  }
  val allOut = if (amountWidth - 1 > levels) sd(amountWidth - 2, levels).orR else false.B
  val beforeExtra = Mux(allOut, 0.U(width.W), shifted)
  val lostBeforeExtra = Mux(allOut, io.din.orR, lostInLevels)

  // The additional level: one more position when the amount came in negative form.
  io.dout := Mux(additionalShift, beforeExtra >> 1, beforeExtra)
  io.sticky := lostBeforeExtra || (additionalShift && beforeExtra(0))
}
