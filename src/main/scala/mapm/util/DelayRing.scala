package mapm.util

import chisel3._
import chisel3.util._

/** A fixed delay of `depth` cycles for values that ride beside a pipeline, as a ring of
  * `depth` − 1 rows and an output register instead of a shift register: a value on `in` in cycle t
  * (with `in.valid`) is written into the row a free-running counter points at; in cycle
  * t + depth − 1 the counter has come round to that row (which is written again only at that
  * cycle's end), and the output register takes it, so it is on `out` in cycle t + depth.
  *
  * Each row has its own clock gate, open only in the cycle its row is written with a valid value,
  * and the output register's gate is open only when `outValid` (the valid bit of the value being
  * read, which the pipeline around keeps anyway) is set. So a value clocks two rows of flip-flops,
  * not `depth` of them as a shift register's stages do; the cost is the counter, a gate per row
  * and a (`depth` − 1)-to-1 read multiplexer, which the output register keeps off the paths of the
  * logic that reads `out`. Without a valid value the rows keep what they hold; `out` is meaningful
  * only in the cycles `depth` after a valid `in`, like the pipeline's data beside its valid bit.
  *
  * Latency: `depth` cycles. Throughput: one value per cycle. Registers: `depth` rows of the
  * value's width (two clocked per value) and a ceil(log2(depth − 1))-bit counter.
  */
class DelayRing[T <: Data](gen: T, val depth: Int) extends Module {
  require(depth >= 3, s"DelayRing: depth $depth (use registers below 3)")
  override def desiredName = s"DelayRing_w${gen.getWidth}_d$depth"

  val io = IO(new Bundle {
    val in = Input(Valid(gen))
    /** The valid bit of the value read this cycle (the one given `depth` − 1 cycles ago). */
    val outValid = Input(Bool())
    val out = Output(gen)
  })

  private val rowCount = depth - 1
  private val at = RegInit(0.U(log2Ceil(rowCount).max(1).W))
  at := Mux(at === (rowCount - 1).U, 0.U, at + 1.U)
  private val rows = (0 until rowCount).map { r =>
    withClock(ClockGate(clock, io.in.valid && at === r.U)) {
      val row = Reg(gen)
      row := io.in.bits
      row
    }
  }
  io.out := withClock(ClockGate(clock, io.outValid)) { RegNext(VecInit(rows)(at)) }
}

object DelayRing {
  /** `x` (valid with `valid`) delayed by `depth` cycles in a [[DelayRing]]; `outValid` is the
    * valid bit of the value given `depth` − 1 cycles before. */
  def apply[T <: Data](x: T, valid: Bool, outValid: Bool, depth: Int): T = {
    val r = Module(new DelayRing(chiselTypeOf(x), depth))
    r.io.in.valid := valid
    r.io.in.bits := x
    r.io.outValid := outValid
    r.io.out
  }
}
