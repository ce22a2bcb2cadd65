package mapm.shader

import mapm.Slow
import mapm.numerics.{FloatFormat, ShaderChainModel}
import org.scalatest.funsuite.AnyFunSuite
import mapm.sim.ShaderChainRunner
import mapm.sim.ShaderChainRunner.Op

/** Exhaustive at n = 5: every combination of the five significands (16^5 = 1,048,576 channel
  * evaluations, three per operation) through the emitted hardware, equal to the bit-accurate
  * model (which ShaderChainModelSpec checks against exact arithmetic on the same set). */
@Slow
class ShaderChainSmallSpec extends AnyFunSuite {
  private val f = FloatFormat(5, 4)

  for (g <- Seq(0, 2, 3)) test(s"$f, g = $g: all 16^5 significand combinations in hardware equal the model") {
    val sim = ShaderChainRunner(f, g)
    val model = new ShaderChainModel(f, g)
    val one = f.bias.toLong << f.manWidth // every exponent at the bias: no special cases
    val pairs = (0 until 256).map(pc => (one | (pc >> 4), one | (pc & 15)))
    val groups = pairs.grouped(3).map(gr => gr.padTo(3, gr.head)).toIndexedSeq // (power, contrib) × 3
    def op(k: Int): Op = {
      val (khb, gi) = (k / groups.length, k % groups.length)
      val pcs = groups(gi)
      Op(Array(one | (khb >> 8), one | ((khb >> 4) & 15), one | (khb & 15)) ++ pcs.map(_._1) ++ pcs.map(_._2), k & 0xffff)
    }
    val count = 4096 * groups.length
    var k = 0
    var checked = 0L
    sim.run(Iterator.tabulate(count)(i => Some(op(i)))) { o =>
      val in = op(k).inputs
      assert(o.tag == (k & 0xffff))
      val front = model.front(in(0), in(1), in(2))
      for (c <- 0 until 3) {
        val want = model.channel(front, in(3 + c), in(6 + c))
        assert(o.colour(c) == want.bits && o.flags(c) == want.flags && want.flags == 0,
          s"inputs ${in.map(f.hex).mkString(",")} channel $c: hardware ${f.hex(o.colour(c))}, model ${f.hex(want.bits)}")
        checked += 1
      }
      k += 1
    }
    assert(k == count && checked >= 16L * 16 * 16 * 256)
  }
}
