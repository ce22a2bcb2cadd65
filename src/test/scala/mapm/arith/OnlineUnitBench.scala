package mapm.arith

import chisel3._
import chisel3.util._
import mapm.numerics.DigitString
import mapm.testutil.Sim

/** A test wrapper around `lanes` copies each of an [[OnlineMul]] (signed-digit operand of
  * `mulXLen` digits) and an [[OnlineDiv]] (dividend of `divXLen` digits), both at n and N =
  * `digits`, that takes whole operands and returns whole digit strings, so that a test streams
  * one operation per unit, lane and cycle through a Verilator pipe without skewing
  * anything itself.
  *
  * Port `io_<u>_in_<l>` (u = mul or div) carries lane l's operation, LSB first: the binary
  * operand (y or d, bit i at bit n − i), the signed-digit operand's pos bits (digit i at bit
  * n + xLen − i) and its neg bits (at bit n + 2·xLen − i). Both bits of a digit go to the unit
  * as they come, so a test can also offer the pair (1,1). Stage s of a unit reads digit/bit s
  * of the operation that entered s − 1 cycles earlier (a delay line of whole operations);
  * output digit i, which the unit presents i + δ cycles after its operation entered, is
  * delayed by N − i registers. Port `io_<u>_out_<l>` therefore carries, N + δ cycles after an
  * operation entered (N + 3 for the multiplier, N + 4 for the divider), its N digits: the pos
  * bits (digit i at bit N − i) and above them the neg bits.
  */
class OnlineUnitBench(val n: Int, val digits: Int, val mulXLen: Int, val divXLen: Int, val lanes: Int) extends Module {
  override def desiredName = s"OnlineUnitBench_n${n}_N${digits}_x${mulXLen}_${divXLen}_l$lanes"

  val io = IO(new Bundle {
    val mul = new Bundle {
      val in = Input(Vec(lanes, UInt((n + 2 * mulXLen).W)))
      val out = Output(Vec(lanes, UInt((2 * digits).W)))
    }
    val div = new Bundle {
      val in = Input(Vec(lanes, UInt((n + 2 * divXLen).W)))
      val out = Output(Vec(lanes, UInt((2 * digits).W)))
    }
  })

  /** Wires one unit (x, binary operand, result ports; δ) to its operation `op` and result port. */
  private def lane(op: UInt, out: UInt, xLen: Int, delta: Int, x: Vec[SignedDigit], b: Vec[Bool], p: Vec[SignedDigit]): Unit = {
    // line(k): the operation that entered k cycles ago (line(0) is the input itself).
    val line = (1 until math.max(xLen, n)).scanLeft(op)((prev, _) => RegNext(prev))
    for (s <- 1 to xLen) {
      x(s - 1).pos := line(s - 1)(n + xLen - s)
      x(s - 1).neg := line(s - 1)(n + 2 * xLen - s)
    }
    for (s <- 1 to n) b(s - 1) := line(s - 1)(n - s)
    def aligned(i: Int, bit: SignedDigit => Bool): Bool = (0 until digits - i).foldLeft(bit(p(i - 1)))((r, _) => RegNext(r))
    out := Cat(Cat((1 to digits).map(i => aligned(i, _.neg))), Cat((1 to digits).map(i => aligned(i, _.pos))))
  }

  for (l <- 0 until lanes) {
    val m = Module(new OnlineMul(n, digits, mulXLen))
    lane(io.mul.in(l), io.mul.out(l), mulXLen, 3, m.io.x, m.io.y, m.io.p)
    val d = Module(new OnlineDiv(n, digits, divXLen))
    lane(io.div.in(l), io.div.out(l), divXLen, 4, d.io.x, d.io.d, d.io.q)
  }
}

/** Streams operations through an [[OnlineUnitBench]] in Verilator (pipes of `sim`, built once per
  * design and cached), one unit at a time. */
final class OnlineUnitSim(sim: Sim, n: Int, digits: Int, mulXLen: Int, divXLen: Int, lanes: Int = 4) {
  private def bench = new OnlineUnitBench(n, digits, mulXLen, divXLen, lanes)
  // rows and outputs: one value per lane
  private lazy val mulPipe = sim.pipe(bench)(_.io.mul.in, _.io.mul.out)
  private lazy val divPipe = sim.pipe(bench)(_.io.div.in, _.io.div.out)

  /** Runs operations 0 until `count` through the multiplier (`mul`) or the divider: `xPos(i)`
    * and `xNeg(i)` are the signed-digit operand's bit masks (digit i at bit xLen − i; a position
    * set in both offers the pair (1,1)), `b(i)` the binary operand (y or d). Calls `sink(i,
    * result)` for every operation, in order, with its N digits as a [[DigitString]]; a result
    * digit (1,1), which no unit may emit, fails. Returns the cycles run. */
  def run(mul: Boolean, count: Int, xPos: Int => Long, xNeg: Int => Long, b: Int => Long)(sink: (Int, DigitString) => Unit): Long = {
    val (u, xLen, latency, pipe) = if (mul) ("mul", mulXLen, digits + 3, mulPipe) else ("div", divXLen, digits + 4, divPipe)
    val opCycles = (count + lanes - 1) / lanes
    val xMask = (1L << xLen) - 1
    val bMask = (1L << n) - 1
    val rows = Iterator.range(0, opCycles + latency).map { c =>
      Array.tabulate(lanes) { l =>
        val i = c * lanes + l
        if (c < opCycles && i < count) BigInt(b(i) & bMask) | (BigInt(xPos(i) & xMask) << n) | (BigInt(xNeg(i) & xMask) << (n + xLen))
        else BigInt(0)
      }
    }
    val mask = (1L << digits) - 1
    var c = -latency
    var seen = 0
    val cycles = pipe.run(rows) { out =>
      if (c >= 0 && c < opCycles) for (l <- 0 until lanes) {
        val i = c * lanes + l
        if (i < count) {
          val v = out(l)
          val (p, m) = ((v & mask).toLong, ((v >> digits) & mask).toLong)
          assert((p & m) == 0, s"$u operation $i: the unit emitted a digit (1,1): pos ${p.toBinaryString}, neg ${m.toBinaryString}")
          sink(i, DigitString(p, m, digits))
          seen += 1
        }
      }
      c += 1
    }
    assert(seen == count, s"${pipe.top}: $seen of $count $u results")
    cycles
  }
}
