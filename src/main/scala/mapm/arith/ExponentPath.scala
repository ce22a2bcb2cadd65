package mapm.arith

import chisel3._
import mapm.util.StageClocks

/** The exponent adder tree of the shader chain (the dissertation's ADD8, generalised to ew-bit
  * exponent fields; shader-chain.md §4): for each channel c,
  * E_0,c = E_k + E_B − E_h + E_p,c + E_c,c + (5 − 2^ew), a signed (ew+3)-bit value. The chain later
  * subtracts the QN step s and the final shift m: E_r = E_0 − s − m.
  *
  * Two cycles, so that neither is a five-operand sum: in the operation's first cycle the shared
  * part E_k + E_B − E_h + 5 − 2^ew and each channel's E_p,c + E_c,c are formed and registered (with
  * `gated`, on `clocks(0)`, the chain's stage clock of that cycle); in the second their sums
  * leave on `e0`.
  *
  * With 1 ≤ E ≤ 2^ew − 2, E_r lies in [6 − 2^(ew+1), 3·2^ew − 4], which ew + 3 bits hold.
  * Latency: one cycle (`e0` in the operation's second cycle). Throughput: one operation per cycle.
  */
class ExponentPath(ew: Int, channels: Int, gated: Boolean = false) extends Module {
  require(ew >= 2 && channels >= 1, s"ExponentPath: ew = $ew, channels = $channels")
  override def desiredName = s"ExponentPath_e${ew}_c$channels${StageClocks.suffix(gated)}"

  val width: Int = ew + 3

  val io = IO(new Bundle {
    val kernel = Input(UInt(ew.W))
    val brdf = Input(UInt(ew.W))
    val h = Input(UInt(ew.W))
    val power = Input(Vec(channels, UInt(ew.W)))
    val contrib = Input(Vec(channels, UInt(ew.W)))
    /** E_0 of each channel, one cycle after the exponents. */
    val e0 = Output(Vec(channels, SInt(width.W)))
    /** clocks(0): the clock of the first cycle's registers (with `gated`). */
    val clocks = StageClocks.port(1, gated)
  })
  private val sc = new StageClocks(io.clocks)

  private def ext(e: UInt): SInt = e.pad(width).asSInt
  private val shared = sc.reg(ext(io.kernel) + ext(io.brdf) - ext(io.h) + (5 - (1 << ew)).S(width.W), 0)
  for (c <- 0 until channels) io.e0(c) := shared + sc.reg(ext(io.power(c)) + ext(io.contrib(c)), 0)
}
