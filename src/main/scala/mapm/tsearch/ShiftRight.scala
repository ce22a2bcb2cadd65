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
  * The shifter is two halves, [[ShiftRight.coarse]] (the upper levels and the whole-word case)
  * and [[ShiftRight.fine]] (the lower levels and the additional level); this module joins them
  * without a register (and is what ShiftUnitsSpec checks exhaustively), the TSA registers between
  * them.
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

  private val coarse = ShiftRight.coarse(io.din, io.dist, 0)
  private val (dout, sticky) = ShiftRight.fine(coarse, Nil, io.dist.extra)
  io.dout := dout
  io.sticky := sticky
}

/** A word part-way through [[ShiftRight]]: shifted by the levels from `from` up, with `lost` set
  * when a 1 bit has been shifted out. A pipeline can register it between the two halves. */
class ShiftPartial(width: Int) extends Bundle {
  val word = UInt(width.W)
  val lost = Bool()
}

object ShiftRight {
  /** Levels that shift by less than the width (2^i for i below it). */
  def levels(width: Int, amountWidth: Int): Int = math.min(log2Ceil(width), amountWidth - 1)

  /** The first half of the shifter: `din` shifted by the levels of `dist` from `from` up, or
    * cleared when the distance reaches the whole word. Combinational. */
  def coarse(din: UInt, dist: ShiftDistance, from: Int): ShiftPartial = {
    val (shifted, lost) = (from until dist.levels).foldLeft((din, false.B)) { case ((v, lost), i) =>
      val k = 1 << i
      (Mux(dist.level(i), v >> k, v), lost || (dist.level(i) && v(k - 1, 0).orR))
    }
    val p = Wire(new ShiftPartial(din.getWidth))
    p.word := Mux(dist.allOut, 0.U, shifted)
    p.lost := Mux(dist.allOut, din.orR, lost)
    p
  }

  /** The second half: the word of [[coarse]]`(din, dist, from)` shifted by the levels below
    * `from` (`lower`: the distance's level bits 0 until `from`), then by the additional level
    * (`extra`); the shifted word and the sticky bit. With `from` = 0 (`lower` empty) it is only
    * the additional level. Combinational. */
  def fine(p: ShiftPartial, lower: Seq[Bool], extra: Bool): (UInt, Bool) = {
    val start = (p.word, p.lost)
    val (shifted, lost) = lower.zipWithIndex.foldLeft(start) { case ((v, lost), (bit, i)) =>
      val k = 1 << i
      (Mux(bit, v >> k, v), lost || (bit && v(k - 1, 0).orR))
    }
    // The additional level: one more position when the amount came in negative form.
    (Mux(extra, shifted >> 1, shifted), lost || (extra && shifted(0)))
  }

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
