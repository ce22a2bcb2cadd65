package mapm.shader

import chisel3._
import chisel3.util._
import mapm.numerics.FloatFormat

/** A test wrapper around 2^`laneBits` copies of [[CondCheck]] for exhaustive runs at a tiny
  * format: in every cycle lane l checks case k = hi·2^laneBits + l of the enumeration of all
  * 2^(7·w) inputs (w = format width; operand j = qx, qy, qz, px, py, pz, h for j = 0 … 6 is bits
  * w·j … w·j + w − 1 of k, as `mapm.numerics.CondTables.operand`), so that one input word `io_hi`
  * per cycle drives 2^laneBits cases. `io_valid` goes to every lane's `in.valid`.
  *
  * Outputs: `io_cond`, lane l's cond at bit l; `io_allValid` and `io_anyValid`, the AND and the
  * OR of the lanes' `out.valid`. The tag input is 0 (the tag path has its own tests).
  */
class CondCheckBench(val fmt: FloatFormat, val laneBits: Int) extends Module {
  private val w = fmt.width
  private val lanes = 1 << laneBits
  require(7 * w > laneBits, s"CondCheckBench: $lanes lanes for a ${7 * w}-bit enumeration")
  override def desiredName = s"CondCheckBench_${fmt.name}_l$lanes"

  val io = IO(new Bundle {
    val valid = Input(Bool())
    val hi = Input(UInt((7 * w - laneBits).W))
    val cond = Output(UInt(lanes.W))
    val allValid = Output(Bool())
    val anyValid = Output(Bool())
  })

  val outs = (0 until lanes).map { l =>
    val c = Module(new CondCheck(fmt, 1))
    val k = Cat(io.hi, l.U(laneBits.W))
    val in = c.io.in.bits
    for ((port, j) <- Seq(in.qx, in.qy, in.qz, in.px, in.py, in.pz, in.h).zipWithIndex) port := k(w * j + w - 1, w * j)
    in.tag := 0.U
    c.io.in.valid := io.valid
    c.io.out
  }
  io.cond := Cat(outs.reverse.map(_.bits.cond))
  io.allValid := outs.map(_.valid).reduce(_ && _)
  io.anyValid := outs.map(_.valid).reduce(_ || _)
}
