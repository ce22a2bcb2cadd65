package mapm.arith

import chisel3._
import chisel3.util._
import mapm.numerics.FloatFormat
import mapm.util.StageClocks

/** Special-case classes of one channel, decided from the input bit patterns (shader-chain.md §2
  * rules 1 and 2). */
class ShaderSpecial extends Bundle {
  /** Rule 1: Inf/NaN anywhere or zero/subnormal h: canonical quiet NaN, INV. */
  val inv = Bool()
  /** Rule 2: a zero or subnormal factor: +0. */
  val zero = Bool()
  /** With `zero`: one of the zero factors was subnormal (flushed): UNF. */
  val flushed = Bool()
}

/** The end of one colour channel (shader-chain.md §3.3, §4, §2): converts the skewed MUL3 digit
  * stream p3 on the fly into the integer V (0 < V < 2^N), finds the shift m ∈ 0 … 4 that brings
  * P3·2^m into [1/2, 1), truncates to n bits, computes E_r = E_0 − s − m and packs the colour,
  * with saturation (OVF), flush (UNF) and the rule 1/2 outputs.
  *
  * Timing: digit p_i must be on `digits(i-1)` in cycle c+i; `e0`, `s`, `sign` and `special` in
  * cycle c+N, together with the last digit. On-the-fly registers follow the digits through
  * cycles c+1 … c+N−1; the last digit, normalization and packing take cycle c+N, and `bits` and
  * `flags` are registered: they appear from cycle c+N+1. One operation per cycle.
  *
  * With `gated`, `clocks(k)` clocks the registers that load at the end of cycle c+k+1 (k = 0 …
  * N−1).
  */
class NormalizePack(format: FloatFormat, digits: Int, gated: Boolean = false) extends Module {
  private val n = format.manWidth + 1
  private val ew = format.expWidth
  require(digits >= n && digits >= 5, s"NormalizePack: N = $digits for n = $n")
  override def desiredName = s"NormalizePack_${format.name}_N$digits${StageClocks.suffix(gated)}"

  val io = IO(new Bundle {
    val digits = Input(Vec(NormalizePack.this.digits, new SignedDigit))
    val e0 = Input(SInt((ew + 3).W))
    val s = Input(Bool())
    val sign = Input(Bool())
    val special = Input(new ShaderSpecial)
    val bits = Output(UInt(format.width.W))
    /** OVF = 1, UNF = 2, INV = 4. */
    val flags = Output(UInt(3.W))
    /** clocks(k): the clock of the registers loading in cycle c+k+1 (with `gated`). */
    val clocks = StageClocks.port(NormalizePack.this.digits, gated)
  })
  private val sc = new StageClocks(io.clocks)

  // On-the-fly conversion along the skew: (Q, QM) after digit i is registered for digit i+1.
  // Only the fraction bits are kept: V > 0, and a sign bit never moves into a fraction bit.
  var (q, qm) = OnTheFly.init
  for (i <- 1 until digits) {
    val (nq, nqm) = OnTheFly.append(q, qm, io.digits(i - 1))
    q = sc.reg(nq(i - 1, 0), i - 1); qm = sc.reg(nqm(i - 1, 0), i - 1)
  }
  val v = OnTheFly.append(q, qm, io.digits(digits - 1))._1

  // m = number of leading zeros of V among its top 5 bits (the ranges guarantee one of them is
  // set); the significand is the n bits from the leading one, with zeros appended when
  // n + m > N (vx carries 4 extra zero bits).
  val lead = (0 until 4).map(k => v(digits - 1 - k)) :+ true.B
  val m = PriorityMux(lead, (0 until 5).map(_.U(3.W)))
  val vx = Cat(v, 0.U(4.W))
  val sig = PriorityMux(lead, (0 until 5).map(k => vx(digits + 3 - k, digits + 4 - n - k)))
  val er = io.e0 - (io.s.asUInt +& m).pad(ew + 3).asSInt

  val maxExp = ((1 << ew) - 1).S((ew + 3).W)
  val ovf = er >= maxExp
  val unf = er <= 0.S
  val sp = io.special
  val bits = Wire(UInt(format.width.W))
  val flags = Wire(UInt(3.W))
  when(sp.inv) {
    bits := format.quietNaN.U; flags := 4.U
  }.elsewhen(sp.zero) {
    bits := 0.U; flags := Mux(sp.flushed, 2.U, 0.U)
  }.elsewhen(ovf) {
    bits := Cat(io.sign, ((1 << ew) - 2).U(ew.W), Fill(format.manWidth, 1.U(1.W))); flags := 1.U
  }.elsewhen(unf) {
    bits := 0.U; flags := 2.U
  }.otherwise {
    bits := Cat(io.sign, er(ew - 1, 0), sig(n - 2, 0)); flags := 0.U
  }
  io.bits := sc.reg(bits, digits - 1)
  io.flags := sc.reg(flags, digits - 1)
}
