package mapm.arith

import chisel3._
import chiseltest._
import mapm.testutil.Sim
import org.scalatest.funsuite.AnyFunSuite

class P2SSpec extends AnyFunSuite with Sim {
  test("bit i of the word entered at t leaves at t + width-1-i, for random back-to-back words") {
    for (width <- Seq(1, 5, 24)) {
      simulate(new P2S(width)) { c =>
        val rnd = new scala.util.Random(width)
        val words = Array.fill(80)(BigInt(width, rnd))
        for (t <- words.indices) {
          c.io.in.poke(words(t).U)
          // Reference: bit i at cycle t comes from the word presented at t - (width-1-i).
          val want = (0 until width).foldLeft(BigInt(0)) { (acc, i) =>
            val src = t - (width - 1 - i)
            if (src >= 0 && words(src).testBit(i)) acc.setBit(i) else acc
          }
          if (t >= width - 1) c.io.out.expect(want.U, s"width $width cycle $t")
          c.clock.step()
        }
      }
    }
  }
}
