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
  * Combinational (no latency); the case sgn = 111 cannot occur and gives zeros.
  */
class ShiftAmountLogic(expWidth: Int) extends RawModule {
  require(expWidth >= 2, s"exponent width must be at least 2, got $expWidth")
  override def desiredName = s"ShiftAmountLogic_e$expWidth"

  val io = IO(new Bundle {
    val pe = Input(UInt(expWidth.W))
    val he = Input(UInt(expWidth.W))
    val se = Input(UInt(expWidth.W))
    /** Shift amounts for p, h, s in the negative-form encoding above. */
    val sap = Output(UInt((expWidth + 1).W))
    val sah = Output(UInt((expWidth + 1).W))
    val sas = Output(UInt((expWidth + 1).W))
  })

  // Zero-extended to expWidth+1 bits, the differences wrap to two's complement.
  private def ext(e: UInt) = Cat(0.U(1.W), e)
  val d0 = ext(io.pe) - ext(io.he)
  val d1 = ext(io.he) - ext(io.se)
  val d2 = ext(io.se) - ext(io.pe)
  val sgn = Cat(d0(expWidth), d1(expWidth), d2(expWidth)) // sgn0 sgn1 sgn2, Table 3.2

  val zero = 0.U((expWidth + 1).W)
  // Table 3.4: (sap, sah, sas) by (sgn0, sgn1, sgn2).
  private val pLargest = Seq(zero, d0, d2) // p.e >= h.e, s.e: h by p.e-h.e, s by -(s.e-p.e)
  private val sLargest = Seq(d2, d1, zero) // s.e largest: p by s.e-p.e, h by -(h.e-s.e)
  private val hLargest = Seq(d0, zero, d1) // h.e largest: p by -(p.e-h.e), s by h.e-s.e
  private val allEqual = Seq(zero, zero, zero)
  private val byCase = Seq(
    "b000" -> allEqual, "b001" -> pLargest, "b010" -> sLargest, "b011" -> pLargest,
    "b100" -> hLargest, "b101" -> hLargest, "b110" -> sLargest)
  private def pick(k: Int): UInt = MuxLookup(sgn, zero)(byCase.map { case (c, outs) => c.U(3.W) -> outs(k) })
  io.sap := pick(0)
  io.sah := pick(1)
  io.sas := pick(2)
}
