package mapm.fpu

import org.scalatest.funsuite.AnyFunSuite

/** PipelinePlan against an exhaustive search over every placement of the registers. */
class PipelinePlanSpec extends AnyFunSuite {
  /** Every cut pattern of `m` steps with `stages` registers, the last step always registered. */
  private def placements(m: Int, stages: Int): Iterator[Seq[Boolean]] =
    if (stages == 0) Iterator(Seq.fill(m)(false))
    else (0 until m - 1).combinations(stages - 1).map(c => (0 until m).map(i => i == m - 1 || c.contains(i)))

  private val rnd = new scala.util.Random(17)
  private val cases = Seq.fill(300) {
    val m = 1 + rnd.nextInt(9)
    Seq.fill(m)((1 + rnd.nextInt(8)) * 0.25)
  }

  test("forStages: the lightest heaviest stage of all placements, with the output registered") {
    for (w <- cases; s <- 0 to w.length) {
      val cuts = PipelinePlan.forStages(w, s)
      assert(cuts.count(identity) == s && (s == 0 || cuts.last), s"$w, $s stages: $cuts")
      val best = placements(w.length, s).map(PipelinePlan.heaviest(w, _)).min
      assert(math.abs(PipelinePlan.heaviest(w, cuts) - best) < 1e-9, s"$w, $s stages: ${PipelinePlan.heaviest(w, cuts)} vs $best")
    }
  }

  /** The steps' weights of each stage under `cuts`. */
  private def stagesOf(w: Seq[Double], cuts: Seq[Boolean]): Seq[Seq[Double]] =
    w.zip(cuts).foldLeft(Seq(Seq.empty[Double])) { case (acc, (x, cut)) =>
      val run = acc.last :+ x
      if (cut) acc.init :+ run :+ Seq.empty else acc.init :+ run
    }.filter(_.nonEmpty)

  test("stagesFor: the fewest registers with every stage within the limit or a single step") {
    for (w <- cases; limit <- Seq(0.5, 1.0, 1.75, 2.0, 3.0)) {
      val s = PipelinePlan.stagesFor(w, limit)
      def fits(k: Int) = placements(w.length, k).exists(c => stagesOf(w, c).forall(st => st.length == 1 || st.sum <= limit + 1e-9))
      assert(fits(s) && (s == 1 || !fits(s - 1)), s"$w, limit $limit: $s stages")
    }
  }

  test("impossible depths are refused with the range") {
    val e = intercept[IllegalArgumentException](PipelinePlan.forStages(Seq(1.0, 1.0), 3))
    assert(e.getMessage.contains("0..2"))
  }

  test("the default depth keeps every stage of FAdd and FMul within the default logic per stage") {
    for (f <- Seq(mapm.numerics.FloatFormat.fp16, mapm.numerics.FloatFormat.fp32, mapm.numerics.FloatFormat.fp64)) {
      val d = FpuDepth.of(f)
      for ((w, s) <- Seq(FAdd.weights(f) -> d.add, FMul.weights(f) -> d.mul))
        assert(PipelinePlan.heaviest(w, PipelinePlan.forStages(w, s)) <= mapm.params.NumberParams.DefaultFpuStageWeight, s"$f $w")
    }
  }
}
