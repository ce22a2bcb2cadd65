package mapm.numerics

import mapm.model.TreeCompare
import mapm.Slow
import mapm.testutil.TsaReference
import org.scalatest.funsuite.AnyFunSuite

/** The TSA model against exact arithmetic (no hardware): exhaustive on small formats, a million
  * seeded hard-case triples at fp32, the dissertation's worked searches, and the bound on the
  * errors of the dissertation's truncating alignment that the guard and sticky bits remove. */
@Slow
class TsaModelSpec extends AnyFunSuite {
  import TsaModel._

  /** Runs `triples` through the model with `al` and returns the ones it decides wrongly. */
  private def wrong(fmt: FloatFormat, triples: Iterator[(Long, Long, Long)], al: Alignment): Seq[(Long, Long, Long)] =
    triples.filter { case (p, h, s) =>
      val o = evaluate(fmt, p, h, s, al)
      o.error || o.tcl != TsaReference.tcl(fmt, p, h, s) || o.tcr != TsaReference.tcr(fmt, p, h, s)
    }.toSeq

  private def all(fmt: FloatFormat): Iterator[(Long, Long, Long)] = {
    val v = TsaReference.allValid(fmt)
    for (p <- v.iterator; h <- v.iterator; s <- v.iterator) yield (p, h, s)
  }

  /** The first wrong triple, for a failure message (the clue is evaluated even on success). */
  private def first(fmt: FloatFormat, bad: collection.Seq[(Long, Long, Long)]): String = bad.headOption.map(show(fmt, _)).getOrElse("")

  private def show(fmt: FloatFormat, t: (Long, Long, Long)): String =
    s"p=${fmt.decode(t._1)} h=${fmt.decode(t._2)} s=${fmt.decode(t._3)} (0x${fmt.hex(t._1)} 0x${fmt.hex(t._2)} 0x${fmt.hex(t._3)})"

  for (fmt <- Seq(FloatFormat(3, 3), FloatFormat(3, 4), FloatFormat(4, 3), FloatFormat(2, 1))) {
    test(s"exhaustive ${fmt.name}: every non-negative finite (p, h, s) matches exact arithmetic") {
      val n = TsaReference.allValid(fmt).size
      val bad = wrong(fmt, all(fmt), Alignment.exact)
      assert(bad.isEmpty, s"${bad.size} of ${n.toLong * n * n} wrong, first ${first(fmt, bad)}")
      info(s"${n.toLong * n * n} triples")
    }
  }

  test("exhaustive e3m3: the dissertation's truncating alignment errs, only within (-2, +1) ulp of the tie") {
    val fmt = FloatFormat(3, 3)
    var errors = 0
    for ((p, h, s) <- all(fmt)) {
      val o = evaluate(fmt, p, h, s, Alignment.dissertation)
      val u = TsaReference.ulp(fmt.expField(p) max fmt.expField(h) max fmt.expField(s))
      val (vp, vh, vs) = (TsaReference.value(fmt, p), TsaReference.value(fmt, h), TsaReference.value(fmt, s))
      // TC_L decides the sign of p - h - s, TC_R that of s - h - p.
      for ((got, want, d) <- Seq((o.tcl, TsaReference.tcl(fmt, p, h, s), vp - vh - vs),
                                 (o.tcr, TsaReference.tcr(fmt, p, h, s), vs - vh - vp)) if got != want) {
        errors += 1
        assert(d > -2 * u && d < u, s"error outside the bound: ${show(fmt, (p, h, s))}")
      }
    }
    assert(errors > 0, "the truncating alignment should lose information somewhere")
    info(s"$errors wrong decisions without guard and sticky bits, all within the bound")
  }

  test("one guard bit alone, or a sticky bit alone, is not enough (e3m3 counterexamples exist)") {
    val fmt = FloatFormat(3, 3)
    for (al <- Seq(Alignment(1, sticky = false), Alignment(0, sticky = true), Alignment(3, sticky = false)))
      assert(wrong(fmt, all(fmt), al).nonEmpty, s"$al unexpectedly exact")
  }

  test("the example of the bound: p = s = 1, h = 2^-30 at fp32") {
    val f = FloatFormat.fp32
    val (p, h, s) = (f.encode(1.0), f.encode(math.pow(2, -30)), f.encode(1.0))
    assert(evaluate(f, p, h, s, Alignment.dissertation) == Outcome(tcl = false, tcr = false, error = false))
    assert(evaluate(f, p, h, s) == Outcome(tcl = true, tcr = true, error = false))
  }

  test("fp32: 1,000,000 seeded hard-case triples match exact arithmetic") {
    val fmt = FloatFormat.fp32
    val gen = new TsaReference.HardCases(fmt, seed = 20140601L)
    val n = 1000000
    var ties, truncationWrong = 0
    val bad = scala.collection.mutable.ArrayBuffer.empty[(Long, Long, Long)]
    for (_ <- 0 until n) {
      val t @ (p, h, s) = gen.next()
      val (vp, vh, vs) = (TsaReference.value(fmt, p), TsaReference.value(fmt, h), TsaReference.value(fmt, s))
      if (vp - vh == vs || vp + vh == vs) ties += 1
      val o = evaluate(fmt, p, h, s)
      if (o.error || o.tcl != (vp - vh < vs) || o.tcr != (vp + vh > vs)) bad += t
      val d = evaluate(fmt, p, h, s, Alignment.dissertation)
      if (d.tcl != (vp - vh < vs) || d.tcr != (vp + vh > vs)) truncationWrong += 1
    }
    assert(bad.isEmpty, s"${bad.size} wrong, first ${first(fmt, bad)}")
    // The generator must reach the hard cases, or the test proves little.
    assert(ties > n / 20, s"only $ties exact ties")
    assert(truncationWrong > n / 200, s"only $truncationWrong cases need the guard and sticky bits")
    info(s"$n triples: $ties exact ties, $truncationWrong that the truncating alignment gets wrong")
  }

  test("other formats: 100,000 seeded hard-case triples each (bf16, fp16, fp24, fp64)") {
    for (fmt <- Seq(FloatFormat.bf16, FloatFormat.fp16, FloatFormat.fp24, FloatFormat.fp64)) {
      val gen = new TsaReference.HardCases(fmt, seed = fmt.width.toLong)
      val bad = wrong(fmt, Iterator.fill(100000)(gen.next()), Alignment.exact)
      assert(bad.isEmpty, s"$fmt: ${bad.size} wrong, first ${first(fmt, bad)}")
    }
  }

  test("agrees with the tree search's TreeCompare on 200,000 fp32 hard-case triples") {
    val fmt = FloatFormat.fp32
    val gen = new TsaReference.HardCases(fmt, seed = 99L)
    for (_ <- 0 until 200000) {
      val (p, h, s) = gen.next()
      val (vp, vh, vs) = (fmt.decode(p), fmt.decode(h), fmt.decode(s))
      assert(evaluate(fmt, p, h, s) == Outcome(TreeCompare.tcL(vp, vh, vs), TreeCompare.tcR(vp, vh, vs), error = false),
        show(fmt, (p, h, s)))
    }
  }

  test("3.1.6 worked searches: TC_L and TC_R at every visited node (h = 100)") {
    val f = FloatFormat.fp32
    // (p, s, TC_L, TC_R) of the three example searches, in the order the nodes are examined.
    val nodes = Seq(
      (280.736, 171.588, false, true), (0.0, 72.7003, true, true),                 // (a) nodes 0, 4
      (255.165, 171.588, true, true), (0.0, 114.27, true, false), (0.0, 72.7003, true, true), // (b) 0, 1, 4
      (26.6906, 171.588, true, false), (213.296, 114.27, true, true))              // (c) nodes 0, 1
    for ((p, s, l, r) <- nodes)
      assert(evaluate(f, f.encode(p), f.encode(100.0), f.encode(s)) == Outcome(l, r, error = false), s"p=$p s=$s")
  }

  test("slice recurrence equals Table 3.7 and decides the sign of A - B - C for all 6-bit words") {
    // Table 3.7 as printed: (carry, p, h, s) -> (result, done).
    val table = Seq("0000" -> "00", "0001" -> "01", "0010" -> "01", "0011" -> "01", "0100" -> "10",
      "0101" -> "00", "0110" -> "00", "0111" -> "01", "1000" -> "11", "1001" -> "10", "1010" -> "10",
      "1011" -> "00", "1100" -> "11", "1101" -> "11", "1110" -> "11", "1111" -> "10")
    for ((in, out) <- table) {
      val st = slice(SliceState(done = false, result = in(0) == '1'), in(1) - '0', in(2) - '0', in(3) - '0')
      assert((st.result, st.done) == (out(0) == '1', out(1) == '1'), s"row $in")
    }
    for (a <- 0 until 64; b <- 0 until 64; c <- 0 until 64) {
      val st = compare(a, b, c, 6)
      val d = a - b - c
      // Decided and negative iff d < 0; result 1 iff d > 0; undecided only for d = 0 or 1.
      assert(less(st) == (d < 0) && st.result == (d > 0) && (st.done || d == 0 || d == 1), s"a=$a b=$b c=$c")
    }
  }

  test("invalid inputs (negative non-zero, infinity, NaN) set error and both TC bits; -0 is zero") {
    val fmt = FloatFormat(3, 3)
    val patterns = (0L until (1L << fmt.width)).toIndexedSeq
    val one = fmt.encode(1.0)
    for (x <- patterns; pos <- 0 until 3) {
      val t = Array(one, one, one); t(pos) = x
      val o = evaluate(fmt, t(0), t(1), t(2))
      val bad = TsaReference.invalid(fmt, x)
      assert(o.error == bad, s"pattern 0x${fmt.hex(x)} at $pos")
      if (bad) assert(o.tcl && o.tcr)
    }
    val negZero = fmt.pack(1, 0, 0)
    assert(evaluate(fmt, negZero, one, one) == evaluate(fmt, 0L, one, one))
  }
}
