package mapm.tsearch

import chisel3._
import chiseltest._
import mapm.arith.P2S
import mapm.testutil.Sim
import org.scalatest.funsuite.AnyFunSuite

class PipelinedComparatorSpec extends AnyFunSuite with Sim {
  /** Parallel words in, through P2S (as in the TSA), into the comparator. */
  class Harness(w: Int) extends Module {
    val io = IO(new Bundle {
      val a = Input(UInt(w.W)); val b = Input(UInt(w.W)); val c = Input(UInt(w.W))
      val done = Output(Bool()); val result = Output(Bool()); val less = Output(Bool())
    })
    val cmp = Module(new PipelinedComparator(w))
    for ((in, port) <- Seq((io.a, cmp.io.a), (io.b, cmp.io.b), (io.c, cmp.io.c))) {
      val p2s = Module(new P2S(w)); p2s.io.in := in; port := p2s.io.out
    }
    io.done := cmp.io.done; io.result := cmp.io.result; io.less := cmp.io.less
  }

  test("every (A, B, C) of 5-bit words, back to back: Table 3.5 outcome after 5 cycles") {
    val w = 5
    simulate(new Harness(w)) { c =>
      val ops = for (a <- 0 until 32; b <- 0 until 32; x <- 0 until 32) yield (a, b, x)
      for (t <- 0 until ops.length + w) {
        if (t < ops.length) { val (a, b, x) = ops(t); c.io.a.poke(a.U); c.io.b.poke(b.U); c.io.c.poke(x.U) }
        if (t >= w) {
          val (a, b, x) = ops(t - w)
          val d = a - b - x
          // Table 3.5: done 1 = decided (result 1 positive, 0 negative); done 0 = tie or +1 unit.
          c.io.less.expect((d < 0).B, s"a=$a b=$b c=$x")
          c.io.result.expect((d > 0).B, s"a=$a b=$b c=$x")
          c.io.done.expect((d < 0 || d >= 2).B, s"a=$a b=$b c=$x")
        }
        c.clock.step()
      }
    }
  }
}
