package mapm.fpu

import chisel3._
import chisel3.util._
import mapm.util.StageClocks

/** Where a unit puts its pipeline registers. A unit is a fixed sequence of combinational steps,
  * each with an estimated delay (its weight, in units of about one full adder; docs/fpu.md); a
  * register may end any step. A plan for `stages` registers always ends the last step with one
  * (the unit's output is registered) and places the others so that the heaviest run of steps
  * between two registers is as light as it can be: the same balancing a pipelining generator does
  * for a target clock. */
object PipelinePlan {
  /** cuts(i): whether a register ends step i, for `stages` registers (0 = all combinational). */
  def forStages(weights: Seq[Double], stages: Int): Seq[Boolean] = {
    val m = weights.length
    require(m >= 1, "a pipelined unit has at least one step")
    require(stages >= 0 && stages <= m, s"a unit of $m steps takes 0..$m register stages, got $stages")
    if (stages == 0) return Seq.fill(m)(false)
    val prefix = weights.scanLeft(0.0)(_ + _)
    def seg(i: Int, j: Int): Double = prefix(j) - prefix(i) // steps i until j
    // best(k)(j): the lightest heaviest segment covering steps 0 until j with k segments.
    val inf = Double.PositiveInfinity
    val best = Array.fill(stages + 1, m + 1)(inf)
    val from = Array.fill(stages + 1, m + 1)(-1)
    best(0)(0) = 0.0
    for (k <- 1 to stages; j <- k to m; i <- (k - 1) until j if best(k - 1)(i) < inf) {
      val c = math.max(best(k - 1)(i), seg(i, j))
      if (c < best(k)(j) - 1e-12) { best(k)(j) = c; from(k)(j) = i }
    }
    val ends = Iterator.iterate((stages, m)) { case (k, j) => (k - 1, from(k)(j)) }
      .takeWhile(_._1 > 0).map(_._2).toSet
    (1 to m).map(ends.contains)
  }

  /** The fewest registers (at least one) such that no run of steps between registers weighs more
    * than `maxWeight`, placed by [[forStages]]; a step heavier than `maxWeight` stands alone. */
  def stagesFor(weights: Seq[Double], maxWeight: Double): Int = {
    require(maxWeight > 0, s"the logic per pipeline stage must be positive, got $maxWeight")
    val (count, _) = weights.foldLeft((1, 0.0)) { case ((n, run), w) =>
      if (run > 0 && run + w > maxWeight + 1e-12) (n + 1, w) else (n, run + w)
    }
    count
  }

  /** The heaviest run of steps between registers under `cuts` (the unit's estimated path). */
  def heaviest(weights: Seq[Double], cuts: Seq[Boolean]): Double =
    weights.zip(cuts).foldLeft((0.0, 0.0)) { case ((worst, run), (w, cut)) =>
      val r = run + w
      if (cut) (worst max r, 0.0) else (worst max r, r)
    }._1
}

/** Builds a unit's datapath step by step: after step i, [[StepPipe.apply]] registers a value when a
  * register ends that step (`cuts(i)`), and passes it through otherwise; [[StepPipe.next]] ends the
  * step and [[StepPipe.finish]] checks that the datapath took exactly as many steps as the plan has.
  * Data registers load every cycle, without an enable: an enable would make the valid bit drive
  * every data register of the stage (a fan-out of thousands in a deep multiplier, measured at
  * 65 MHz), and the valid bit beside the data tells which cycles carry an operation. With an
  * `enable` (a unit inside a pipeline that stalls, such as the conventional TSA in its Tree Search
  * Module) every register, valid bit included, loads only while it is high. With stage clocks
  * (`clocks`, a unit in a stage-gated pipeline), the data registers of the k-th register stage
  * run on clock k, gated by the valid bit beside them; the valid bits keep the module clock. */
final class StepPipe(val cuts: Seq[Boolean], inValid: Bool, enable: Option[Bool] = None,
                     clocks: StageClocks = new StageClocks(None)) {
  require(enable.isEmpty || clocks.port.isEmpty, "a stallable pipeline has no stage clocks")
  private var step = 0
  private var stage = 0 // register stages before the current step
  private var validNow: Bool = inValid

  /** The valid bit beside the values of the current step. */
  def valid: Bool = validNow

  /** `x` across the end of the current step. */
  def apply[T <: Data](x: T): T = {
    require(step < cuts.length, s"datapath has more than the ${cuts.length} planned steps")
    if (cuts(step)) clocks.at(stage) { // keeps x's width, as RegNext would not
      val r = Reg(chiselTypeOf(x))
      enable match { case Some(en) => when(en) { r := x }; case None => r := x }
      r
    } else x
  }

  /** Ends the current step; values of the next step are read through [[apply]] first. */
  def next(): Unit = {
    require(step < cuts.length, s"datapath has more than the ${cuts.length} planned steps")
    if (cuts(step)) {
      validNow = RegEnable(validNow, false.B, enable.getOrElse(true.B))
      stage += 1
    }
    step += 1
  }

  /** `x` across the end of the current step, which it then ends: the step's one value. */
  def last[T <: Data](x: T): T = { val r = apply(x); next(); r }

  /** The unit's output valid bit, after checking that every planned step was taken. */
  def finish(): Bool = {
    require(step == cuts.length, s"datapath took $step steps, the plan has ${cuts.length}")
    validNow
  }
}

/** A unit whose registers follow a [[PipelinePlan]] of its steps: `stages` is its latency. */
private[fpu] trait PlannedPipeline { this: Module =>
  /** Estimated delay of each step. */
  def weights: Seq[Double]
  /** Register stages: the latency in cycles. */
  def stages: Int
  lazy val cuts: Seq[Boolean] = PipelinePlan.forStages(weights, stages)
  def latency: Int = stages
}
