package mapm.pipeline

import java.nio.file.Path

import mapm.format.SlotLayout
import mapm.model.QueryOrder
import mapm.numerics.{Arith, FloatFormat}
import mapm.params.{Fidelity, Hierarchy}
import mapm.sim.Harness

/** Everything a run through the RTL is made from, as one value that the command line builds from
  * its options (`mapm.cli.RtlOptions.settings`) and passes down to [[RtlRun]] and to the
  * evaluation: the scene and its number format, the arithmetic and fidelity, the hardware sizes
  * ([[Tuning]]), the harness's memory model and limits, and where the files go.
  *
  * @param scene    scene description file
  * @param format   number format, else the scene's, else fp32
  * @param layout   slot layout of the memory records
  * @param g        guard digits of the SOA's online units
  * @param arith    arithmetic of the SOAs and TSAs
  * @param fidelity full RTL, or the SOAs as their timing model
  * @param harness  the harness's memory model, limits and waveform
  * @param out      output folder
  * @param threads  worker threads of the model
  * @param tuning   the memory hierarchy and the hardware sizes given
  * @param queryOrder the order in which the host streams the queries ([[RunSettings.defaultOrder]] unless given)
  */
final case class RunSettings(
    scene: String,
    format: Option[FloatFormat],
    layout: SlotLayout,
    g: Int,
    arith: Arith,
    fidelity: Fidelity,
    harness: Harness.RunOptions,
    out: String,
    threads: Int,
    tuning: Tuning,
    queryOrder: QueryOrder = QueryOrder.Morton) {

  /** The run's work folder under [[out]], as [[RtlRun.setup]] names it: `<scene>-rtl`, or
    * `<scene>-conv-rtl` for the conventional arithmetic. */
  def workDir: Path = RtlRun.workDir(scene, arith, out)

  /** The text of these settings for a run archive's key, on the scene file `scene` as named
    * relative to the checkout: everything but the output folder and the worker threads. */
  def archiveText(scene: String): String =
    copy(scene = scene, out = "", threads = 1, harness = harness.copy(simThreads = 1)).toString

  /** [[RtlRun.configure]]: the scene, format and configurations `configs` checked, without running the model. */
  def check(configs: Seq[(Int, Int, Int)]): Unit = {
    RtlRun.configure(scene, format, g, configs, layout, arith, fidelity, tuning)
    ()
  }

  /** Resolves the scene, format and configurations `configs` (TSM/SOM/SOA) and prepares the frame ([[RtlRun.setup]]). */
  def setup(configs: Seq[(Int, Int, Int)], prebuild: Option[(Boolean, Int)] = None, log: String => Unit = _ => ()): RtlRun.Setup =
    RtlRun.setup(scene, format, g, configs, out, threads, layout, arith, fidelity, tuning, prebuild, log, queryOrder)
}

object RunSettings {
  /** The host's query order when none is given: Morton order for the scalable hierarchy (its SOP L1
    * banks then hold the photons that the queries in flight share; docs/uncore.md), the
    * renderer's own order for Table 4.2's, as the dissertation's host streamed them. */
  def defaultOrder(h: Hierarchy): QueryOrder = h match {
    case Hierarchy.Scalable => QueryOrder.Morton
    case Hierarchy.Table42  => QueryOrder.Host
  }
}
