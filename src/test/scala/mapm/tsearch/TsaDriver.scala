package mapm.tsearch

import chisel3._
import chiseltest._
import mapm.numerics.FloatFormat
import mapm.numerics.TsaModel.Outcome
import org.scalatest.Assertions

/** Streams operations through a [[TSA]] or [[ConvTSA]] under chiseltest and checks what comes out.
  *
  * Each cycle an operation is offered (valid high) unless a random gap is drawn; its tag is its
  * index modulo 2^tagWidth. Every response must come exactly `latency` cycles after its request,
  * in order, with the request's tag; `check` then judges its outputs. */
object TsaDriver extends Assertions {
  final case class Op(p: Long, h: Long, s: Long)

  /** [[stream]] with `expected(op)` as the only right outcome, and `also(op, outcome)` for further
    * checks; asserts that every operation was answered. Returns the cycles taken. */
  def checkAll(c: TsaUnit, fmt: FloatFormat, tagWidth: Int, ops: IndexedSeq[Op], gapProb: Double = 0.0)
              (expected: Op => Outcome, also: (Op, Outcome) => Unit = (_, _) => ()): Long = {
    var checked = 0
    val cycles = stream(c, fmt, tagWidth, ops, gapProb) { (i, op, hw) =>
      val want = expected(op)
      assert(hw == want, s"op $i: p=0x${fmt.hex(op.p)} h=0x${fmt.hex(op.h)} s=0x${fmt.hex(op.s)}: hardware $hw, expected $want")
      also(op, hw)
      checked += 1
    }
    assert(checked == ops.length)
    cycles
  }

  /** Runs `ops` with valid gaps of probability `gapProb` (seeded), then drains the pipeline;
    * calls `check(index, op, response)` per response. Returns the cycles taken. */
  def stream(c: TsaUnit, fmt: FloatFormat, tagWidth: Int, ops: IndexedSeq[Op], gapProb: Double = 0.0, seed: Long = 1)
            (check: (Int, Op, Outcome) => Unit): Long = {
    val rnd = new scala.util.Random(seed)
    val issuedAt = new Array[Long](ops.length)
    val tagMask = (BigInt(1) << tagWidth) - 1
    var next = 0 // next op to offer
    var seen = 0 // responses received
    var cycle = 0L
    c.clock.setTimeout(0)
    while (seen < ops.length) {
      val offer = next < ops.length && !(gapProb > 0 && rnd.nextDouble() < gapProb)
      c.io.in.valid.poke(offer.B)
      if (offer) {
        val o = ops(next)
        c.io.in.bits.p.poke(o.p.U(fmt.width.W)); c.io.in.bits.h.poke(o.h.U(fmt.width.W)); c.io.in.bits.s.poke(o.s.U(fmt.width.W))
        c.io.in.bits.tag.poke((BigInt(next) & tagMask).U(tagWidth.W))
        issuedAt(next) = cycle
        next += 1
      }
      if (c.io.out.valid.peek().litToBoolean) {
        assert(seen < next, s"response at cycle $cycle with no request outstanding")
        assert(cycle - issuedAt(seen) == c.latency, s"op $seen: latency ${cycle - issuedAt(seen)}, expected ${c.latency}")
        val tag = c.io.out.bits.tag.peek().litValue
        assert(tag == (BigInt(seen) & tagMask), s"op $seen came back with tag $tag: out of order or lost")
        check(seen, ops(seen), Outcome(c.io.out.bits.tcl.peek().litToBoolean,
          c.io.out.bits.tcr.peek().litToBoolean, c.io.out.bits.error.peek().litToBoolean))
        seen += 1
      } else assert(seen >= next || cycle - issuedAt(seen) < c.latency, s"op $seen lost: no response at cycle $cycle")
      c.clock.step()
      cycle += 1
    }
    cycle
  }
}
