package mapm.tsearch

import mapm.Slow
import mapm.numerics.{ConvTsaModel, FloatFormat, SoftFloat}
import mapm.numerics.TsaModel.Outcome
import mapm.testutil.{Sim, TsaReference}
import org.scalatest.funsuite.AnyFunSuite
import TsaDriver.Op

/** The conventional TSA: its rule (rounded sums, comparisons, the rounding's direction at a tie)
  * against exact decisions in the model, then the hardware against exact decisions. */
@Slow
class ConvTSASpec extends AnyFunSuite with Sim {

  private def exact(fmt: FloatFormat, p: Long, h: Long, s: Long): Outcome =
    if (Seq(p, h, s).exists(TsaReference.invalid(fmt, _))) Outcome(tcl = true, tcr = true, error = true)
    else Outcome(TsaReference.tcl(fmt, p, h, s), TsaReference.tcr(fmt, p, h, s), error = false)

  test("model: exhaustive e3m3 and e4m3 (every non-negative finite triple), the rule equals the exact decisions") {
    for (fmt <- Seq(FloatFormat(3, 3), FloatFormat(4, 3))) {
      val v = TsaReference.allValid(fmt)
      var ties = 0
      for (p <- v; h <- v; s <- v) {
        val want = exact(fmt, p, h, s)
        assert(ConvTsaModel.evaluate(fmt, p, h, s) == want, s"$fmt p=${fmt.hex(p)} h=${fmt.hex(h)} s=${fmt.hex(s)}")
        // Count the cases a rounded comparison alone would get wrong: the direction decides them.
        val rl = SoftFloat.sub(fmt, p, h)
        if (SoftFloat.lt(fmt, rl, s) != want.tcl) ties += 1
      }
      info(s"$fmt: ${v.length * v.length * v.length} triples, $ties where a plain rounded p - h < s is wrong")
      assert(ties > 0, "the exhaustive set must contain cases where rounding alone flips the decision")
    }
  }

  test("model: fp32 and fp16, 1,000,000 hard-case triples each, the rule equals the exact decisions") {
    for (fmt <- Seq(FloatFormat.fp32, FloatFormat.fp16)) {
      val gen = new TsaReference.HardCases(fmt, seed = 2718L + fmt.width)
      for (_ <- 0 until 1000000) {
        val (p, h, s) = gen.next()
        assert(ConvTsaModel.evaluate(fmt, p, h, s) == exact(fmt, p, h, s), s"$fmt p=${fmt.hex(p)} h=${fmt.hex(h)} s=${fmt.hex(s)}")
      }
    }
  }

  private def checkAll(c: ConvTSA, fmt: FloatFormat, tagWidth: Int, ops: IndexedSeq[Op], gapProb: Double = 0.0): Long =
    TsaDriver.checkAll(c, fmt, tagWidth, ops, gapProb)(o => exact(fmt, o.p, o.h, o.s))

  test("hardware: e3m3 exhaustive, back to back, equals the exact decisions") {
    val fmt = FloatFormat(3, 3)
    val v = TsaReference.allValid(fmt)
    val ops = for (p <- v; h <- v; s <- v) yield Op(p, h, s)
    simulate(new ConvTSA(fmt, tagWidth = 5, addStages = 3)) { c =>
      assert(c.latency == 5)
      val cycles = checkAll(c, fmt, 5, ops)
      assert(cycles == ops.length + c.latency, "one operation per cycle")
    }
  }

  test("hardware: fp32, 100,000 hard-case triples back to back and 20,000 with gaps and invalid inputs; depths 0 and 9") {
    val fmt = FloatFormat.fp32
    val gen = new TsaReference.HardCases(fmt, seed = 1618L)
    val random = IndexedSeq.fill(100000) { val (p, h, s) = gen.next(); Op(p, h, s) }
    val rnd = new scala.util.Random(8)
    def maybeBad(x: Long) = if (rnd.nextInt(15) == 0) rnd.nextLong() & fmt.mask else x
    val gappy = IndexedSeq.fill(20000) { val (p, h, s) = gen.next(); Op(maybeBad(p), maybeBad(h), maybeBad(s)) }
    assert(gappy.count(o => exact(fmt, o.p, o.h, o.s).error) > 1000, "the invalid inputs must be exercised")
    simulate(new ConvTSA(fmt, tagWidth = 8, addStages = 9)) { c =>
      assert(c.latency == 11)
      assert(checkAll(c, fmt, 8, random) == random.length + c.latency)
      checkAll(c, fmt, 8, gappy, gapProb = 0.3)
    }
    simulate(new ConvTSA(fmt, tagWidth = 8, addStages = 0)) { c =>
      assert(c.latency == 2)
      checkAll(c, fmt, 8, gappy.take(5000), gapProb = 0.3)
    }
  }
}
