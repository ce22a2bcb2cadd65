package mapm.tsearch

import mapm.Slow
import mapm.numerics.{FloatFormat, TsaModel}
import mapm.numerics.TsaModel.Outcome
import mapm.testutil.{Sim, TsaReference}
import org.scalatest.funsuite.AnyFunSuite
import TsaDriver.Op

/** The TSA hardware against exact arithmetic and the bit-accurate model. */
@Slow
class TSASpec extends AnyFunSuite with Sim {

  /** Exact outcome of a valid triple; an invalid one flags error and sets both bits. */
  private def exact(fmt: FloatFormat, o: Op): Outcome =
    if (Seq(o.p, o.h, o.s).exists(TsaReference.invalid(fmt, _))) Outcome(tcl = true, tcr = true, error = true)
    else Outcome(TsaReference.tcl(fmt, o.p, o.h, o.s), TsaReference.tcr(fmt, o.p, o.h, o.s), error = false)

  /** Streams `ops` and asserts hardware = exact = model for every one. */
  private def checkAll(c: TSA, fmt: FloatFormat, tagWidth: Int, ops: IndexedSeq[Op], gapProb: Double = 0.0): Long =
    TsaDriver.checkAll(c, fmt, tagWidth, ops, gapProb)(exact(fmt, _), (op, hw) =>
      assert(TsaModel.evaluate(fmt, op.p, op.h, op.s) == hw, s"$op: model disagrees with hardware $hw"))

  test("e3m3 exhaustive: all 175,616 non-negative finite (p, h, s) back to back, hardware = exact = model") {
    val fmt = FloatFormat(3, 3)
    val v = TsaReference.allValid(fmt)
    val ops = for (p <- v; h <- v; s <- v) yield Op(p, h, s)
    simulate(new TSA(fmt, tagWidth = 5)) { c =>
      assert(c.latency == fmt.manWidth + 7)
      val cycles = checkAll(c, fmt, 5, ops)
      assert(cycles == ops.length + c.latency, "one operation per cycle")
      info(s"${ops.length} operations in $cycles cycles (latency ${c.latency})")
    }
  }

  test("fp32: 100,000 seeded hard-case triples, the 3.1.6 searches, and 20,000 with random valid gaps and invalid inputs") {
    val fmt = FloatFormat.fp32
    val gen = new TsaReference.HardCases(fmt, seed = 31416L)
    val random = IndexedSeq.fill(100000) { val (p, h, s) = gen.next(); Op(p, h, s) }
    // 3.1.6, h = 100: (p, s) at each visited inner node of the three example searches.
    val worked = Seq((280.736, 171.588), (0.0, 72.7003), (255.165, 171.588), (0.0, 114.27), (0.0, 72.7003),
      (26.6906, 171.588), (213.296, 114.27)).map { case (p, s) => Op(fmt.encode(p), fmt.encode(100.0), fmt.encode(s)) }
    val wantWorked = Seq((false, true), (true, true), (true, true), (true, false), (true, true), (true, false), (true, true))
    // Random gaps; one operand in 15 replaced by an arbitrary pattern (about half are negative, Inf or NaN).
    val rnd = new scala.util.Random(7)
    def maybeBad(x: Long) = if (rnd.nextInt(15) == 0) rnd.nextLong() & fmt.mask else x
    val gappy = IndexedSeq.fill(20000) { val (p, h, s) = gen.next(); Op(maybeBad(p), maybeBad(h), maybeBad(s)) }
    assert(gappy.count(o => exact(fmt, o).error) > 1000, "the invalid inputs must be exercised")

    simulate(new TSA(fmt, tagWidth = 8)) { c =>
      assert(c.latency == 30)
      val cycles = checkAll(c, fmt, 8, random)
      assert(cycles == random.length + c.latency, "one operation per cycle")

      TsaDriver.stream(c, fmt, 8, worked.toIndexedSeq) { (i, _, hw) =>
        assert((hw.tcl, hw.tcr, hw.error) == (wantWorked(i)._1, wantWorked(i)._2, false), s"3.1.6 node visit $i")
      }

      checkAll(c, fmt, 8, gappy, gapProb = 0.3)
      info(s"${random.length} back-to-back + ${worked.length} worked + ${gappy.length} with gaps (latency ${c.latency})")
    }
  }
}
