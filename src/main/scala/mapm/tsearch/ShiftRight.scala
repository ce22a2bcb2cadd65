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

/** A word part-way through [[ShiftRight]]: shifted by the levels from some level up, with `lost`
  * set when a 1 bit has been shifted out. A pipeline can register it between the two halves. */
class ShiftPartial(width: Int) extends Bundle {
  val word = UInt(width.W)
  val lost = Bool()
}

/** Shift Right (3.4.4): a barrel shifter that aligns a significand by the distance that
  * [[ShiftAmountLogic]] hands over, with a sticky output for the bits it drops.
  *
  * The amount is `amountWidth`-bit two's complement in the negative form ([[decode]]): when its
  * sign bit is 0 the distance is the amount; when it is 1 the distance is -amount, realised as
  * sd = ~amount (which is -amount - 1) through the ordinary levels plus an additional final level
  * that shifts by one more. Levels shift by 2^i for i < log2Ceil(width); a distance with a higher
  * bit set shifts everything out, and so does any distance of `width` or more: the output is then
  * zero. Zeros are shifted in. The sticky bit is the OR of every bit shifted out (it lets the TSA
  * keep the comparison exact; see `mapm.numerics.TsaModel`).
  *
  * The shifter comes in three combinational pieces so that a pipeline can register between them
  * (the TSA registers after each): [[decode]] (amount to [[ShiftDistance]]), [[coarse]] (the levels
  * from a split level up, and the whole-word case) and [[fine]] (the levels below the split, and
  * the additional level). ShiftUnitsSpec checks decode, coarse and fine together exhaustively, at
  * every split.
  */
object ShiftRight {
  /** Levels that shift by less than the width (2^i for i below it). */
  def levels(width: Int, amountWidth: Int): Int = math.min(log2Ceil(width), amountWidth - 1)

  /** The [[ShiftDistance]] of the negative-form amount `si` (`amountWidth` bits) for a
    * `width`-bit word. */
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

  /** `(word, lost)` shifted by 2^i for each (bit, i) of `steps` whose bit is set, `lost` gathering
    * the 1 bits shifted out. */
  private def shiftBy(word: UInt, lost: Bool, steps: Seq[(Bool, Int)]): (UInt, Bool) =
    steps.foldLeft((word, lost)) { case ((v, l), (bit, i)) =>
      val k = 1 << i
      (Mux(bit, v >> k, v), l || (bit && v(k - 1, 0).orR))
    }

  /** The first half: `din` shifted by the levels of `dist` from `split` up, or cleared when the
    * distance reaches the whole word. */
  def coarse(din: UInt, dist: ShiftDistance, split: Int): ShiftPartial = {
    val (shifted, lost) = shiftBy(din, false.B, (split until dist.levels).map(i => (dist.level(i), i)))
    val p = Wire(new ShiftPartial(din.getWidth))
    p.word := Mux(dist.allOut, 0.U, shifted)
    p.lost := Mux(dist.allOut, din.orR, lost)
    p
  }

  /** The second half: the [[coarse]] result `p` shifted by the levels below the split (`lower`:
    * the distance's level bits 0 until the split), then by the additional level (`extra`); the
    * aligned word and the sticky bit. */
  def fine(p: ShiftPartial, lower: Seq[Bool], extra: Bool): (UInt, Bool) = {
    val (shifted, lost) = shiftBy(p.word, p.lost, lower.zipWithIndex)
    // The additional level: one more position when the amount came in negative form.
    (Mux(extra, shifted >> 1, shifted), lost || (extra && shifted(0)))
  }
}
