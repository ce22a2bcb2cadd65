package mapm.util

import chisel3._
import chisel3.util._

/** A fixed delay of `depth` cycles for values that ride beside a pipeline, as a ring of `depth`
  * rows instead of a shift register: a value on `in` in cycle t (with `in.valid`) is written into
  * the row a free-running counter points at, and is on `out` in cycle t + depth, read from the
  * same row (the counter has come round; the row is written again only at the end of that cycle).
  *
  * Each row has its own clock gate, open only in the cycle its row is written with a valid value,
  * so an operation clocks one row of flip-flops, not `depth` of them as a shift register's
  * stages do; the cost is the counter, one clock gate per row and a `depth`-to-1 read multiplexer.
  * Without a valid value the rows keep what they hold; `out` is meaningful only in the cycles
  * `depth` after a valid `in`, like the pipeline's data beside its valid bit.
  *
  * Latency: `depth` cycles. Throughput: one value per cycle. Registers: `depth` rows of the
  * value's width (each clocked once per value) and a ceil(log2 depth)-bit counter.
  */
class DelayRing[T <: Data](gen: T, val depth: Int) extends Module {
  require(depth >= 2, s"DelayRing: depth $depth (use a register below 2)")
  override def desiredName = s"DelayRing_w${gen.getWidth}_d$depth"

  val io = IO(new Bundle {
    val in = Input(Valid(gen))
    val out = Output(gen)
  })

  private val at = RegInit(0.U(log2Ceil(depth).W))
  at := Mux(at === (depth - 1).U, 0.U, at + 1.U)
  private val rows = (0 until depth).map { r =>
    withClock(ClockGate(clock, io.in.valid && at === r.U)) {
      val row = Reg(gen)
      row := io.in.bits
      row
    }
  }
  io.out := VecInit(rows)(at)
}

object DelayRing {
  /** `x` (valid with `valid`) delayed by `depth` cycles in a [[DelayRing]]. */
  def apply[T <: Data](x: T, valid: Bool, depth: Int): T = {
    val r = Module(new DelayRing(chiselTypeOf(x), depth))
    r.io.in.valid := valid
    r.io.in.bits := x
    r.io.out
  }
}
