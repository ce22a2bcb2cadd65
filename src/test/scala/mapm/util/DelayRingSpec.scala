package mapm.util

import chisel3._
import chiseltest._
import mapm.testutil.Sim
import org.scalatest.funsuite.AnyFunSuite

/** The delay ring against a reference queue of the values it was given: under a seeded random
  * valid pattern (with garbage on the data input in the idle cycles, and `outValid` set exactly
  * for the values being read), every value given with `valid` is on `out` exactly `depth` cycles
  * later, for two depths; and the rule that picks a ring over a shift register. */
class DelayRingSpec extends AnyFunSuite with Sim {
  for (depth <- Seq(3, 13))
    test(s"depth $depth: each valid value is on out exactly $depth cycles later") {
      simulate(new DelayRing(UInt(8.W), depth)) { c =>
        val rnd = new scala.util.Random(depth)
        val given = scala.collection.mutable.Map.empty[Int, Int] // cycle -> value
        var checked = 0
        for (t <- 0 until 400) {
          val valid = rnd.nextInt(3) != 0
          val v = rnd.nextInt(256)
          c.io.outValid.poke(given.contains(t - depth + 1).B)
          c.io.in.valid.poke(valid.B)
          c.io.in.bits.poke(v.U)
          if (valid) given(t) = v
          given.remove(t - depth).foreach { want => c.io.out.expect(want.U, s"cycle $t"); checked += 1 }
          c.clock.step()
        }
        assert(checked > 200)
      }
    }

  test("a ring where it clocks fewer flip-flops per value than a shift register (2 width + 2 depth < width x depth)") {
    assert(StageGates.ringPays(24, 10) && StageGates.ringPays(45, 43) && StageGates.ringPays(5, 5))
    assert(!StageGates.ringPays(1, 34) && !StageGates.ringPays(4, 4) && !StageGates.ringPays(64, 2))
  }
}
