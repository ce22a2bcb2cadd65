package mapm.cost

import mapm.MapmError

/** The shortest clock period at which a design meets setup, found from its worst slack at a few
  * trial periods, for a design too large to bisect (each trial re-times millions of cells).
  *
  * The worst slack s(P) is the least of every path's slack, and it does not fall as the period
  * grows. A path between flip-flops has slack `a P - d`, where `a` is the fraction of the period
  * between its launch and capture edges (1 from one rising edge to the next) and `d` its delay. A
  * path into a latch transparent while the clock is low (a clock gate's enable latch) gets half a
  * period (a = 1/2) and then borrows time from the latch's transparent half: its slack stays 0
  * while the borrowed time lets the path out of the latch meet. So the period needed is not
  * `P - s(P)` (that assumes a = 1: with a latch path worst at P it gives P/2 + d where at most 2d
  * is needed), and a slack of 0 does not say the period cannot be shorter.
  *
  * The search keeps the longest period known to fail and the shortest known to meet, and stops
  * when they are within `toleranceNs` (or after `maxTrials`), returning the shortest meeting
  * period. With no failing period yet, it steps from the meeting one by the slope of the last two
  * meeting trials (1 at first); at a slack within the tolerance it probes just below, and if that
  * meets at slack 0 too (a latch borrowing) it halves the period. With both ends it tries, in this
  * order: a little above a failing trial within a quarter tolerance of meeting; the period where
  * the failing side's line reaches 0 (the slope of the last two failing trials, or 1 from one:
  * exact when one path rules there), confirmed by a trial just below the meeting end when it
  * lands on it; the chord of the two ends (Illinois: an end kept twice in a row has its slack
  * halved), unless the meeting end's slack is 0; the middle.
  */
object PeriodSearch {
  /** The period found (it meets: slack at least 0), its slack, and every trial (period, slack). */
  final case class Result(periodNs: Double, slackNs: Double, trials: Seq[(Double, Double)])

  def minPeriod(slackAt: Double => Double, startNs: Double, toleranceNs: Double = 0.001, maxTrials: Int = 12): Result = {
    MapmError.check(startNs > 0 && toleranceNs > 0 && maxTrials >= 2, s"period search: start $startNs ns, tolerance $toleranceNs ns, $maxTrials trials")
    val trials = Vector.newBuilder[(Double, Double)]
    var count = 0
    def trial(p: Double): Double = {
      val s = slackAt(p)
      MapmError.check(!s.isNaN, s"period search: no slack at $p ns")
      trials += p -> s; count += 1; s
    }
    // A meeting period first: a failing trial P with slack s < 0 moves to P - 2 s, which meets
    // when no failing path's slope is below 1/2; it repeats otherwise.
    var (hi, sHi) = (startNs, trial(startNs))
    while (sHi < 0) {
      MapmError.check(count < maxTrials, s"period search: no period up to $hi ns meets timing (slack $sHi ns)")
      hi -= 2 * sHi; sHi = trial(hi)
    }
    var meets = List(hi -> sHi)    // the meeting trials, newest first
    var fails = List.empty[(Double, Double)]
    var (lo, sLo) = (Double.NaN, Double.NaN)
    var (keptLo, keptHi) = (0, 0)  // trials in a row that left that end where it was (Illinois)
    def slope(a: (Double, Double), b: (Double, Double)): Double = (a._2 - b._2) / (a._1 - b._1)
    def inside(p: Double): Boolean = p > lo + toleranceNs / 4 && p < hi - toleranceNs / 4
    while (!(hi - lo <= toleranceNs) && count < maxTrials) {
      val next =
        if (lo.isNaN) {
          if (sHi > toleranceNs) {
            val a = meets match { case x :: y :: _ => slope(x, y); case _ => 1.0 }
            math.max(hi - sHi / math.max(a, 1e-3), hi / 8)
          } else if (meets.lengthCompare(2) >= 0 && meets(1)._2 <= toleranceNs) hi / 2
          else hi - toleranceNs
        } else {
          // The failing side's line: along the slope of the last two failing trials, or 1 from one.
          val along = fails match { case x :: y :: _ => x._1 - x._2 / slope(x, y); case x :: _ => x._1 - x._2; case _ => Double.NaN }
          val (h, l) = (if (keptHi >= 2) sHi / 2 else sHi, if (keptLo >= 2) sLo / 2 else sLo)
          val chord = hi - h * (hi - lo) / (h - l)
          // A failing trial this close to the root (a step along its own path lands there, but
          // rounding may leave its slack a hair below zero): a little above it meets.
          val near = lo - 2 * sLo + toleranceNs / 4
          if (-sLo <= toleranceNs / 4 && near < hi) near
          else if (math.abs(along - hi) <= toleranceNs / 4) hi - toleranceNs / 2 // the root is the meeting end: confirm
          else if (inside(along)) along
          else if (sHi > 0 && inside(chord)) chord
          else (lo + hi) / 2
        }
      val s = trial(next)
      if (s >= 0) { hi = next; sHi = s; meets = (next -> s) :: meets; keptLo += 1; keptHi = 0 }
      else { lo = next; sLo = s; fails = (next -> s) :: fails; keptHi += 1; keptLo = 0 }
    }
    Result(hi, sHi, trials.result())
  }
}
