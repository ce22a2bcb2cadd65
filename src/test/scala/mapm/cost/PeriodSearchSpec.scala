package mapm.cost

import mapm.MapmError
import org.scalatest.funsuite.AnyFunSuite

/** [[PeriodSearch]] against designs whose answer is known exactly. A design is a set of paths.
  * A path between flip-flops has a delay d and the fraction a of the period it gets (1 from a
  * rising edge to the next): slack a P - d, needing d / a. A path into a clock gate's enable latch
  * (open from the falling edge, P/2, to the next rising one) has a delay d to the latch and `out`
  * from the latch to the gate, due at P. Into the latch its slack is P/2 - d while that is
  * positive and 0 while it borrows (d > P/2); out of it, the path leaves at max(d, P/2), so its
  * slack is P - max(d, P/2) - out. It needs d + out when out < d (borrowing), else 2 out. The
  * worst slack is the least of the paths', and the period needed the largest of theirs. */
class PeriodSearchSpec extends AnyFunSuite {
  private final case class Path(a: Double, d: Double, out: Double = Double.NaN) {
    def slack(p: Double): Double =
      if (out.isNaN) a * p - d
      else math.min(if (p / 2 >= d) p / 2 - d else 0.0, p - math.max(d, p / 2) - out)
    def needs: Double = if (out.isNaN) d / a else if (out < d) d + out else 2 * out
  }
  private def slack(ps: Seq[Path])(p: Double): Double = ps.map(_.slack(p)).min
  private def needed(ps: Seq[Path]): Double = ps.map(_.needs).max

  private def check(ps: Seq[Path], start: Double, tol: Double = 0.001): PeriodSearch.Result = {
    val r = PeriodSearch.minPeriod(slack(ps), start, tol)
    val exact = needed(ps)
    assert(slack(ps)(r.periodNs) >= 0, s"$ps: ${r.periodNs} ns misses (trials ${r.trials})")
    assert(r.periodNs - exact <= tol, s"$ps: ${r.periodNs} ns found, $exact ns needed (trials ${r.trials})")
    assert(r.slackNs == slack(ps)(r.periodNs) && r.trials.contains(r.periodNs -> r.slackNs))
    r
  }

  test("one full-period path: the slack at the first trial gives the period, a trial a tolerance below it fails") {
    val r = check(Seq(Path(1, 3.2)), 10)
    assert(r.trials.size == 3 && math.abs(r.periodNs - 3.2) < 1e-12 && r.trials(2)._2 < 0, r.trials.toString)
  }

  test("a clock gate's latch path (half a period) worst at the trial period, a slower full-period path at the root") {
    // As in the 16/16/2: at 10 ns the worst slack is the latch path's, 5 - 1.4 = 3.6 ns, so
    // "period minus slack" says 6.4 ns; the design needs 5.1 ns (the full-period path).
    val ps = Seq(Path(0.5, 1.4), Path(1, 5.1), Path(1, 2.0))
    assert(math.abs((10 - slack(ps)(10)) - 6.4) < 1e-12)
    val r = check(ps, 10)
    assert(math.abs(r.periodNs - 5.1) <= 0.002 && r.trials.size <= 6, r.trials.toString)
    // The latch path alone needs 2.8 ns, not the 6.4 the one-step guess gives.
    assert(math.abs(check(Seq(Path(0.5, 1.4)), 10).periodNs - 2.8) <= 0.002)
  }

  test("a design slower than the first trial period: the search moves out until it meets, then in") {
    val r = check(Seq(Path(1, 18.5), Path(0.5, 12.0)), 10)
    assert(r.periodNs >= 24 && r.periodNs <= 24.002)
  }

  test("a latch that borrows: slack 0 over a range of periods, the shortest of them found") {
    // 1.4 ns into the latch, 0.2 ns after it: 2.8 ns without borrowing, 1.6 ns with it.
    val r = check(Seq(Path(0.5, 1.4, 0.2)), 10)
    assert(math.abs(r.periodNs - 1.6) <= 0.001 && r.trials.exists(t => t._2 == 0 && t._1 > 1.7), r.trials.toString)
  }

  test("20,000 seeded designs of 1 to 40 paths, a third of them with latches: the period found meets and is within a tolerance of the exact one") {
    val rnd = new scala.util.Random(35)
    var worst = 0
    val counts = (0 until 20000).map { _ =>
      def delay = 0.05 + rnd.nextDouble() * rnd.nextDouble() * 20
      val ps = Seq.fill(1 + rnd.nextInt(40))(rnd.nextInt(3) match {
        case 0 => Path(1, delay); case 1 => Path(0.5, delay); case _ => Path(0.5, delay, rnd.nextDouble() * 3) })
      val n = check(ps, Seq(10.0, 2.0, 50.0)(rnd.nextInt(3))).trials.size
      worst = math.max(worst, n); n
    }
    info(f"trials: mean ${counts.sum.toDouble / counts.size}%.2f, most $worst")
    assert(worst <= 12)
  }

  test("a slack that never turns positive, or no slack at all, is a one-line error") {
    val e = intercept[MapmError](PeriodSearch.minPeriod(_ => -1.0, 10))
    assert(e.getMessage.contains("no period up to") && !e.getMessage.contains("\n"))
    assert(intercept[MapmError](PeriodSearch.minPeriod(_ => Double.NaN, 10)).getMessage.contains("no slack at 10.0 ns"))
    assert(intercept[MapmError](PeriodSearch.minPeriod(slack(Seq(Path(1, 1))), 0)).getMessage.contains("start 0.0 ns"))
  }
}
