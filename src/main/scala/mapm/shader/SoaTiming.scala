package mapm.shader

import chisel3._
import chisel3.util._
import mapm.fpu.FpuDepth
import mapm.numerics.{Arith, FloatFormat}

/** The timing model of an [[SOA]] (`--fidelity timing`, docs/harness.md): a delay line of exactly
  * the SOA's latency carrying `valid` and the tag (the pixel, query and photon indices), and with
  * `cond` the SOA's own cond check ([[CondCheck]]), delayed as the SOA delays it.
  *
  * The SOA takes one operation per cycle, never stalls and gives each result a fixed
  * [[SOA.latency]] later in input order, and nothing around it reads a result's colour or cond:
  * the SOM lane passes them out of the MAPM. So a MAPM with this model in every lane is cycle for
  * cycle the same machine at its ports: the same results with the same indices on the same ports
  * in the same cycles, the same stalls and counters, except `soPassed`, which counts cond bits the
  * model does not compute. Colour, flags and cond read as zero; the harness takes them from the
  * expected SOs (`MAPM_FIDELITY_TIMING`) and says so. `MapmTimingSpec` proves the equivalence.
  * The coprocessor's frame accumulator takes the SOs whose cond holds, so its timing depends on
  * cond: there the model computes it (`cond`), and the machine is cycle for cycle the full one's.
  *
  * Latency: [[SOA.latency]] of the same arguments. Throughput: one operation per cycle.
  */
class SoaTiming(val format: FloatFormat, val g: Int, val tagWidth: Int = 16,
                val condDepth: Option[FpuDepth] = None, val arith: Arith = Arith.Online, val cond: Boolean = false) extends ShaderUnit {
  private val depth = condDepth.getOrElse(FpuDepth.of(format))
  val latency: Int = SOA.latency(format, g, depth, arith)
  override def desiredName: String = s"SoaTiming_${format.name}_t${tagWidth}_l$latency${if (cond) "_cond" else ""}"

  val io = IO(new SoaIO(format, tagWidth))
  io.out.valid := ShiftRegister(io.in.valid, latency, false.B, true.B)
  io.out.bits.tag := ShiftRegister(io.in.bits.tag, latency)
  io.out.bits.colour.foreach(_ := 0.U)
  io.out.bits.flags.foreach(_ := 0.U)
  if (cond) {
    val check = Module(new CondCheck(format, 1, depth))
    check.io.in.valid := io.in.valid
    check.io.in.bits.qx := io.in.bits.qx
    check.io.in.bits.qy := io.in.bits.qy
    check.io.in.bits.qz := io.in.bits.qz
    check.io.in.bits.px := io.in.bits.px
    check.io.in.bits.py := io.in.bits.py
    check.io.in.bits.pz := io.in.bits.pz
    check.io.in.bits.h := io.in.bits.h
    check.io.in.bits.tag := 0.U
    io.out.bits.cond := ShiftRegister(check.io.out.bits.cond, latency - check.latency)
  } else io.out.bits.cond := false.B
}
