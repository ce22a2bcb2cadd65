package mapm.tsearch

import chisel3._
import chisel3.util._

/** Shift Amount Logic (3.4.3): from the biased exponent fields of p, h and s, the right-shift
  * distance of each significand that aligns it to the largest of the three exponents.
  *
  * Three (expWidth+1)-bit subtractors give d0 = p.e - h.e, d1 = h.e - s.e, d2 = s.e - p.e; their
  * sign bits (sgn0, sgn1, sgn2, Table 3.2) name a largest exponent (Table 3.3) and each output
  * is 0, a non-negative difference, or a NEGATIVE difference (Table 3.4). A negative output -k
  * is not negated here (that would take a second carry-propagate adder): [[ShiftRight]] shifts
  * by ~(-k) = k-1 and one additional level of 1, which finishes the two's complement.
  *
  * Outputs are (expWidth+1)-bit two's complement: sign bit set means "shift by the negation".
  * Combinational: two pieces, [[differences]] (the subtractors) and [[select]] (Table 3.4), so
  * that a pipeline can register the differences between them (the TSA does); the case sgn = 111
  * cannot occur and gives zeros. ShiftUnitsSpec checks the two together exhaustively.
  */
object ShiftAmountLogic {
  /** The three subtractors: d0 = p.e - h.e, d1 = h.e - s.e, d2 = s.e - p.e, each (expWidth+1)
    * bits (the exponents zero-extended, the differences wrapping to two's complement). */
  def differences(pe: UInt, he: UInt, se: UInt): Seq[UInt] = {
    def ext(e: UInt) = Cat(0.U(1.W), e)
    Seq(ext(pe) - ext(he), ext(he) - ext(se), ext(se) - ext(pe))
  }

  /** Table 3.4: the shift amounts (sap, sah, sas) from the differences (d0, d1, d2), chosen by
    * their sign bits (sgn0 sgn1 sgn2, Table 3.2). */
  def select(d: Seq[UInt]): Seq[UInt] = {
    val Seq(d0, d1, d2) = d
    val w = d0.getWidth
    val sgn = Cat(d0(w - 1), d1(w - 1), d2(w - 1))
    val zero = 0.U(w.W)
    val pLargest = Seq(zero, d0, d2) // p.e >= h.e, s.e: h by p.e-h.e, s by -(s.e-p.e)
    val sLargest = Seq(d2, d1, zero) // s.e largest: p by s.e-p.e, h by -(h.e-s.e)
    val hLargest = Seq(d0, zero, d1) // h.e largest: p by -(p.e-h.e), s by h.e-s.e
    val allEqual = Seq(zero, zero, zero)
    val byCase = Seq(
      "b000" -> allEqual, "b001" -> pLargest, "b010" -> sLargest, "b011" -> pLargest,
      "b100" -> hLargest, "b101" -> hLargest, "b110" -> sLargest)
    (0 until 3).map(k => MuxLookup(sgn, zero)(byCase.map { case (c, outs) => c.U(3.W) -> outs(k) }))
  }
}
