package mapm.fpu

import mapm.numerics.FloatFormat
import mapm.params.NumberParams

/** Register stages (latency in cycles) of each conventional floating-point unit: [[FAdd]],
  * [[FMul]], [[FCmpLt]] and [[FDiv]]. The one pipeline-depth parameter of the conventional
  * arithmetic, shared by every unit built from them (the SOA's cond check, the conventional SOA
  * and TSA). */
final case class FpuDepth(add: Int, mul: Int, cmp: Int, div: Int) {
  require(add >= 0 && mul >= 0 && cmp >= 0 && cmp <= 1 && div >= 0,
    s"FPU stages must be non-negative (compare 0 or 1), got add $add, mul $mul, cmp $cmp, div $div")
}

object FpuDepth {
  /** The fewest stages for each unit of format `fmt` with no more than `stageWeight` of logic
    * between registers: a pipeline depth chosen for a target clock, as FloPoCo chooses one. */
  def of(fmt: FloatFormat, stageWeight: Double = NumberParams.DefaultFpuStageWeight): FpuDepth =
    FpuDepth(PipelinePlan.stagesFor(FAdd.weights(fmt), stageWeight),
      PipelinePlan.stagesFor(FMul.weights(fmt), stageWeight), 1,
      PipelinePlan.stagesFor(FDiv.weights(fmt), stageWeight))
}
