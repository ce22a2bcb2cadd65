package mapm.arith

import chisel3._

/** The exponent adder tree of the shader chain (the dissertation's ADD8, generalised to ew-bit
  * exponent fields; shader-chain.md §4): for each channel c,
  * E_0,c = E_k + E_B − E_h + E_p,c + E_c,c + (5 − 2^ew), a signed (ew+3)-bit value. The chain later
  * subtracts the QN step s and the final shift m: E_r = E_0 − s − m. The shared part
  * E_k + E_B − E_h + 5 − 2^ew is formed once for all channels.
  *
  * With 1 ≤ E ≤ 2^ew − 2, E_r lies in [6 − 2^(ew+1), 3·2^ew − 4], which ew + 3 bits hold.
  * Combinational (no latency); the chain registers the result.
  */
class ExponentPath(ew: Int, channels: Int) extends Module {
  require(ew >= 2 && channels >= 1, s"ExponentPath: ew = $ew, channels = $channels")
  override def desiredName = s"ExponentPath_e${ew}_c$channels"

  val width: Int = ew + 3

  val io = IO(new Bundle {
    val kernel = Input(UInt(ew.W))
    val brdf = Input(UInt(ew.W))
    val h = Input(UInt(ew.W))
    val power = Input(Vec(channels, UInt(ew.W)))
    val contrib = Input(Vec(channels, UInt(ew.W)))
    val e0 = Output(Vec(channels, SInt(width.W)))
  })

  private def ext(e: UInt): SInt = e.pad(width).asSInt
  private val shared = ext(io.kernel) + ext(io.brdf) - ext(io.h) + (5 - (1 << ew)).S(width.W)
  for (c <- 0 until channels) io.e0(c) := shared + ext(io.power(c)) + ext(io.contrib(c))
}
