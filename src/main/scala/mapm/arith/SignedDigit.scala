package mapm.arith

import chisel3._
import chisel3.util._

/** A radix-2 signed digit as the pair (pos, neg) with value pos − neg (online-arithmetic.md §0):
  * +1 = (1,0), 0 = (0,0), −1 = (0,1). No unit produces (1,1); a consumer reads it as 0. */
class SignedDigit extends Bundle {
  val pos = Bool()
  val neg = Bool()

  def isPlus: Bool = pos && !neg
  def isMinus: Bool = neg && !pos
  def isZero: Bool = pos === neg
}

object SignedDigit {
  def apply(pos: Bool, neg: Bool): SignedDigit = {
    val d = Wire(new SignedDigit)
    d.pos := pos
    d.neg := neg
    d
  }
  def zero: SignedDigit = apply(false.B, false.B)
}

/** Carry-save helpers shared by the online units. */
object CarrySave {
  /** CSA(a, b, c) over `w` bits: (a ⊕ b ⊕ c, majority(a, b, c) shifted left by one with bit 0
    * = 0); the carry out of the top bit is dropped. */
  def csa(a: UInt, b: UInt, c: UInt, w: Int): (UInt, UInt) = {
    val sum = a ^ b ^ c
    val maj = (a & b) | (a & c) | (b & c)
    (sum(w - 1, 0), (maj << 1)(w - 1, 0))
  }

  /** Registers bits hi … lo of `v` for the next pipeline stage and returns them as a `width`-bit
    * vector with zeros above hi and below lo (bits that can no longer reach a result). */
  def keep(v: UInt, hi: Int, lo: Int, width: Int): UInt = {
    val r = StageReg(v(hi, lo))
    val above = if (hi + 1 < width) Some(0.U((width - 1 - hi).W)) else None
    val below = if (lo > 0) Some(0.U(lo.W)) else None
    Cat((above.toSeq :+ r) ++ below.toSeq)
  }
}

/** On-the-fly conversion (online-arithmetic.md §3): registers Q and QM = Q − 2^-k, each a sign
  * bit and k fraction bits (a (k+1)-bit two's-complement integer in units of 2^-k). Appending
  * a digit writes one new bit into each, with multiplexers only and no carries. */
object OnTheFly {
  /** The start: Q = 0 and QM = −1, with no fraction bits. */
  def init: (UInt, UInt) = (0.U(1.W), 1.U(1.W))

  /** (Q, QM) after digit `d` at fraction position k+1: +1 gives (Q‖1, Q‖0), 0 gives (Q‖0,
    * QM‖1), −1 gives (QM‖1, QM‖0). */
  def append(q: UInt, qm: UInt, d: SignedDigit): (UInt, UInt) = {
    val nq = Mux(d.isMinus, Cat(qm, 1.U(1.W)), Cat(q, d.isPlus))
    val nqm = Mux(d.isPlus, Cat(q, 0.U(1.W)), Cat(qm, !d.isMinus))
    (nq, nqm)
  }

  /** [[append]] followed by truncation of Q to `keepQ` and QM to `keepQm` leading fraction
    * bits, for registers whose low bits can no longer reach a result. When neither keeps the
    * new digit's position, the digit still selects between Q and QM (a borrow or carry can
    * change every held bit): Q' = (d = −1 ? QM : Q) and QM' = (d = +1 ? Q : QM), truncated. */
  def appendKeeping(q: UInt, qm: UInt, d: SignedDigit, keepQ: Int, keepQm: Int): (UInt, UInt) = {
    def trunc(v: UInt, k: Int): UInt = v >> (v.getWidth - 1 - k) // sign and k fraction bits
    val (fq, fqm) = (q.getWidth - 1, qm.getWidth - 1)
    if (keepQ > fq || keepQm > fqm) {
      require(fq == fqm && keepQ <= fq + 1 && keepQm <= fq + 1, s"on-the-fly append: $fq/$fqm bits, keep $keepQ/$keepQm")
      val (nq, nqm) = append(q, qm, d)
      (trunc(nq, keepQ), trunc(nqm, keepQm))
    } else {
      require(keepQ <= fqm && keepQm <= fq, s"on-the-fly update: $fq/$fqm bits, keep $keepQ/$keepQm")
      (Mux(d.isMinus, trunc(qm, keepQ), trunc(q, keepQ)), Mux(d.isPlus, trunc(q, keepQm), trunc(qm, keepQm)))
    }
  }
}

/** A register that keeps the exact type and width of its input (`RegNext` leaves widths to
  * inference, but the pipelines read the widths of their registered state while elaborating). */
object StageReg {
  def apply[T <: Data](next: T): T = mapm.util.StageGates.register(next)
}
