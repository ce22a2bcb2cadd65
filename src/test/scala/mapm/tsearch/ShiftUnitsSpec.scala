package mapm.tsearch

import mapm.Slow
import chisel3._
import chiseltest._
import mapm.testutil.Sim
import org.scalatest.funsuite.AnyFunSuite

/** The alignment units, exhaustively against plain integer references. */
@Slow
class ShiftUnitsSpec extends AnyFunSuite with Sim {
  /** [[ShiftAmountLogic.differences]] then [[ShiftAmountLogic.select]], as the TSA uses them. */
  class SalHarness(e: Int) extends Module {
    val io = IO(new Bundle {
      val pe, he, se = Input(UInt(e.W))
      val sap, sah, sas = Output(UInt((e + 1).W))
    })
    private val Seq(p, h, s) = ShiftAmountLogic.select(ShiftAmountLogic.differences(io.pe, io.he, io.se))
    io.sap := p; io.sah := h; io.sas := s
  }
  /** [[ShiftRight.decode]] of a negative-form amount `si`, [[ShiftRight.coarse]] from level `split`
    * up and [[ShiftRight.fine]] below it, combinationally (the TSA registers between them). */
  class ShiftRightHarness(w: Int, a: Int, split: Int) extends Module {
    val io = IO(new Bundle {
      val din = Input(UInt(w.W))
      val si = Input(UInt(a.W))
      val dout = Output(UInt(w.W))
      val sticky = Output(Bool())
    })
    private val d = ShiftRight.decode(io.si, w, a)
    private val (dout, sticky) = ShiftRight.fine(ShiftRight.coarse(io.din, d, split), (0 until split).map(d.level(_)), d.extra)
    io.dout := dout
    io.sticky := sticky
  }

  /** The distance a negative-form amount stands for: its absolute value. */
  private def distance(si: BigInt, bits: Int): Int = {
    val v = if (si.testBit(bits - 1)) si - (BigInt(1) << bits) else si
    v.abs.toInt
  }

  test("ShiftAmountLogic: every exponent triple (4-bit exponents) gives largest - own, zero for the largest") {
    val e = 4
    simulate(new SalHarness(e)) { c =>
      for (pe <- 0 until 16; he <- 0 until 16; se <- 0 until 16) {
        c.io.pe.poke(pe.U); c.io.he.poke(he.U); c.io.se.poke(se.U)
        val m = pe max he max se
        for ((port, own, name) <- Seq((c.io.sap, pe, "p"), (c.io.sah, he, "h"), (c.io.sas, se, "s")))
          assert(distance(port.peek().litValue, e + 1) == m - own, s"shift of $name for exponents ($pe, $he, $se)")
      }
    }
  }

  test("ShiftRight: every word and amount (width 6, 4-bit and 5-bit amounts) at every split, negative form and sticky") {
    for ((w, a) <- Seq((6, 4), (5, 5)); split <- 0 to ShiftRight.levels(w, a)) {
      simulate(new ShiftRightHarness(w, a, split)) { c =>
        for (din <- 0 until (1 << w); si <- 0 until (1 << a)) {
          c.io.din.poke(din.U); c.io.si.poke(si.U)
          val d = distance(si, a)
          val want = if (d >= w) 0 else din >> d
          val lost = if (d >= w) din != 0 else (din & ((1 << d) - 1)) != 0
          c.io.dout.expect(want.U, s"w=$w split=$split din=$din si=$si (distance $d)")
          c.io.sticky.expect(lost.B, s"sticky w=$w split=$split din=$din si=$si")
        }
      }
    }
  }
}
