package mapm.shader

import chisel3._
import chiseltest._
import mapm.model.{DigitString, OnlineArith}
import mapm.testutil.Sim
import org.scalatest.funsuite.AnyFunSuite

/** The online multiplier and divider alone, in hardware, exhaustively at n = 8: every operation
  * streamed back to back through the skewed pipeline; each digit string equals the model's
  * and is within 2^-N of the exact product or quotient. */
class OnlineUnitsSpec extends AnyFunSuite with Sim {
  private val n = 8

  /** Drives a skewed unit: op k enters stage 1 in cycle k; stage s reads operand digit/bit s of
    * the op it holds; output digit i of op k is read in cycle k + i + delta. Returns the
    * digit strings in op order. */
  private def stream(n: Int, ops: IndexedSeq[(DigitString, Long)], delta: Int, digits: Int,
                      x: Vec[SignedDigit], y: Vec[Bool], out: Vec[SignedDigit], clock: Clock): IndexedSeq[DigitString] = {
    val pos = Array.fill(ops.length)(0L); val neg = Array.fill(ops.length)(0L)
    clock.setTimeout(0)
    for (c <- 0 until ops.length + digits + delta + 1) {
      for (s <- 1 to x.length) {
        val k = c - s + 1
        val d = if (k >= 0 && k < ops.length) ops(k)._1.digit(s) else 0
        x(s - 1).pos.poke((d > 0).B); x(s - 1).neg.poke((d < 0).B)
      }
      for (s <- 1 to y.length) {
        val k = c - s + 1
        y(s - 1).poke((k >= 0 && k < ops.length && ((ops(k)._2 >>> (n - s)) & 1L) == 1L).B)
      }
      for (i <- 1 to digits) {
        val k = c - i - delta
        if (k >= 0 && k < ops.length) {
          if (out(i - 1).pos.peek().litToBoolean) pos(k) |= 1L << (digits - i)
          if (out(i - 1).neg.peek().litToBoolean) neg(k) |= 1L << (digits - i)
        }
      }
      clock.step()
    }
    ops.indices.map(k => DigitString(pos(k), neg(k), digits))
  }

  private def bits8(v: Int): DigitString = DigitString.ofBits(v, n)

  /** A random signed-digit string with leading +1 (a chain operand: every prefix ≥ 0); every
    * other digit is nonzero with probability `density`: sparse strings have long zero runs,
    * after which a −1 borrows through every bit of the on-the-fly registers. */
  private def chainDigits(rnd: scala.util.Random, len: Int, density: Double = 2.0 / 3): DigitString = {
    var p = 1L << (len - 1); var m = 0L
    for (i <- 0 until len - 1 if rnd.nextDouble() < density) if (rnd.nextBoolean()) p |= 1L << i else m |= 1L << i
    DigitString(p, m, len)
  }

  // At n = 24 the last stages hold trimmed state (low residual, X, Y, Q/QM and D bits), which the
  // n = 8 units barely exercise; random and sparse operands against the model cover it.
  for (g <- Seq(0, 3)) test(s"OnlineMul and OnlineDiv n = 24, N = ${24 + g}: 5,000 random operations each match the model") {
    val m = 24; val nd = m + g
    val rnd = new scala.util.Random(24 + g)
    def sig(): Long =
      if (rnd.nextInt(4) == 0) (1L << m) - 1 - (rnd.nextLong() & 3) // near all ones
      else (1L << (m - 1)) | (rnd.nextLong() & ((1L << (m - 1)) - 1))
    def digits(): DigitString = chainDigits(rnd, nd, if (rnd.nextBoolean()) 2.0 / 3 else 0.08)
    val mulOps = IndexedSeq.fill(5000)((digits(), sig()))
    simulate(new OnlineMul(m, nd, nd)) { c =>
      val got = stream(m, mulOps, 3, nd, c.io.x, c.io.y, c.io.p, c.clock)
      for (((x, y), p) <- mulOps.zip(got)) assert(p == OnlineArith.mul(x, y, m, nd), s"x = $x, y = $y")
    }
    val divOps = IndexedSeq.fill(5000) { // x' = (0, p) with p a product-like digit string
      val p = digits(); (DigitString(p.pos, p.neg, nd + 1), sig())
    }
    simulate(new OnlineDiv(m, nd, nd + 1)) { c =>
      val got = stream(m, divOps, 4, nd, c.io.x, c.io.d, c.io.q, c.clock)
      for (((x, d), q) <- divOps.zip(got)) assert(q == OnlineArith.div(x, d, m, nd), s"x' = $x, d = $d")
    }
  }

  for (g <- Seq(0, 3)) test(s"OnlineMul n = 8, N = ${n + g}: all 256 x 128 operand pairs match the model and are within 2^-N") {
    val nd = n + g
    val rnd = new scala.util.Random(g)
    // Every 8-bit x (as digits 0/1) times every normalized y, then random signed-digit x.
    val signed = Seq.fill(4000) {
      val p = rnd.nextInt(256); DigitString(p, rnd.nextInt(256) & ~p, n)
    }
    val ops = ((for (x <- 0 until 256; y <- 128 until 256) yield (bits8(x), y.toLong)) ++
      signed.map(x => (x, 128L + rnd.nextInt(128)))).toIndexedSeq
    simulate(new OnlineMul(n, nd, n)) { c =>
      val got = stream(n, ops, 3, nd, c.io.x, c.io.y, c.io.p, c.clock)
      for (((x, y), p) <- ops.zip(got)) {
        assert(p == OnlineArith.mul(x, y, n, nd), s"x = $x, y = ${y.toBinaryString}")
        assert(math.abs(x.scaled * y * (1L << nd) - p.scaled * (1L << 16)) < (1L << 16), s"x = $x, y = $y: $p")
      }
    }
  }

  for (g <- Seq(0, 3)) test(s"OnlineDiv n = 8, N = ${n + g}: all 256 x 128 dividend/divisor pairs match the model and are within 2^-N") {
    val nd = n + g
    val rnd = new scala.util.Random(10 + g)
    // Dividends (0, x_1 … x_8): every 8-bit x, then random signed-digit x.
    val signed = Seq.fill(4000) {
      val p = rnd.nextInt(256); DigitString(p, rnd.nextInt(256) & ~p, n + 1)
    }
    val ops = ((for (x <- 0 until 256; d <- 128 until 256) yield (DigitString.ofBits(x, n + 1), d.toLong)) ++
      signed.map(x => (x, 128L + rnd.nextInt(128)))).toIndexedSeq
    simulate(new OnlineDiv(n, nd, n + 1)) { c =>
      val got = stream(n, ops, 4, nd, c.io.x, c.io.d, c.io.q, c.clock)
      for (((x, d), q) <- ops.zip(got)) {
        assert(q == OnlineArith.div(x, d, n, nd), s"x' = $x, d = ${d.toBinaryString}")
        assert(math.abs(x.scaled * (1L << nd) - q.scaled * d * 2) < 2 * d, s"x' = $x, d = $d: $q")
      }
    }
  }
}
