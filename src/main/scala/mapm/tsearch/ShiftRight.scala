package mapm.tsearch

import chisel3._
import chisel3.util._

/** A shift distance as [[ShiftRight]]'s levels take it: the bit of each level (shift by 2^i),
  * whether the word is shifted out whole (`allOut`), and whether one more position follows
  * (`extra`, the negative form's additional level). [[ShiftRight.decode]] makes it from the
  * negative-form amount; a pipeline can register it between the two. */
class ShiftDistance(val levels: Int) extends Bundle {
  val level = UInt(levels.W)
  val allOut = Bool()
  val extra = Bool()
}

/** Shift Right (3.4.4): a barrel shifter that aligns a significand by a [[ShiftDistance]], with a
  * sticky output for the bits it drops.
  *
  * The distance comes from the amount that [[ShiftAmountLogic]] hands over, `amountWidth`-bit two's
  * complement in the negative form ([[ShiftRight.decode]]): when its sign bit is 0 the distance is
  * the amount; when it is 1 the distance is -amount, realised as sd = ~amount (which is -amount - 1)
  * through the ordinary levels plus an additional final level that shifts by one more. Levels
  * shift by 2^i for i < log2Ceil(width); a distance with a higher bit set shifts everything out,
  * and so does any distance of `width` or more: the output is then zero. Zeros are shifted in.
  * `sticky` is the OR of every bit shifted out (it lets the TSA keep the comparison exact; see
  * `mapm.model.TsaModel`).
  *
  * Combinational (no latency).
  */
class ShiftRight(width: Int, amountWidth: Int) extends RawModule {
  require(width >= 1, s"shifter width must be at least 1, got $width")
  require(amountWidth >= 2, s"amount width must be at least 2 (sign and one bit), got $amountWidth")
  override def desiredName = s"ShiftRight_w${width}_a$amountWidth"

  val io = IO(new Bundle {
    val din = Input(UInt(width.W))
    val dist = Input(new ShiftDistance(ShiftRight.levels(width, amountWidth)))
    val dout = Output(UInt(width.W))
    /** Some 1 bit of din was shifted out. */
    val sticky = Output(Bool())
  })

  private val sd = io.dist.level
  val (shifted, lostInLevels) = (0 until io.dist.levels).foldLeft((io.din, false.B)) { case ((v, lost), i) =>
    val k = 1 << i
    (Mux(sd(i), v >> k, v), lost || (sd(i) && v(k - 1, 0).orR))
  }
  val beforeExtra = Mux(io.dist.allOut, 0.U(width.W), shifted)
  val lostBeforeExtra = Mux(io.dist.allOut, io.din.orR, lostInLevels)

  // The additional level: one more position when the amount came in negative form.
  io.dout := Mux(io.dist.extra, beforeExtra >> 1, beforeExtra)
  io.sticky := lostBeforeExtra || (io.dist.extra && beforeExtra(0))
}

object ShiftRight {
  /** Levels that shift by less than the width (2^i for i below it). */
  def levels(width: Int, amountWidth: Int): Int = math.min(log2Ceil(width), amountWidth - 1)

  /** The [[ShiftDistance]] of the negative-form amount `si` (`amountWidth` bits) for a
    * `width`-bit word. Combinational. */
  def decode(si: UInt, width: Int, amountWidth: Int): ShiftDistance = {
    require(si.getWidth == amountWidth, s"shift amount is ${si.getWidth} bits, expected $amountWidth")
    val n = levels(width, amountWidth)
    val d = Wire(new ShiftDistance(n))
    val extra = si(amountWidth - 1)
    val magnitude = si(amountWidth - 2, 0)
    val sd = Mux(extra, ~magnitude, magnitude)
    d.level := sd(n - 1, 0)
    d.allOut := (if (amountWidth - 1 > n) sd(amountWidth - 2, n).orR else false.B)
    d.extra := extra
    d
  }
}
