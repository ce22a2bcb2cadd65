package mapm.cli

import mapm.pipeline.RunSettings

import java.nio.file.Path

import mainargs.{arg, main}
import mapm.format.SlotLayout
import mapm.model.{Parallel, QueryOrder}
import mapm.numerics.{Arith, FloatFormat}
import mapm.sim.Harness
import mapm.params.Fidelity
import Args.{ArithReader, FidelityReader, FloatFormatReader, QueryOrderReader, SlotLayoutReader}

/** The options `render`, `sweep` and `evaluate` share ([[mapm.pipeline.RtlRun]]): the scene and its number format, the
  * harness's memory model and limits ([[Harness.RunOptions]]), the output folder, the model's
  * threads and the hardware sizes ([[HwOptions]]). Each command takes it as one parameter;
  * mainargs lists its flags with the command's own. The command passes them down as a
  * [[RunSettings]]. */
@main
final case class RtlOptions(
    @arg(doc = "scene description file (JSON)") scene: String = RenderCommand.defaultScene,
    @arg(doc = "number format (default: the scene's, else fp32)") format: Option[FloatFormat] = None,
    @arg(doc = "memory records: packed (format slots of 2, 4 or 8 bytes, the smallest that fits) or wide (at least 4)") layout: SlotLayout = SlotLayout.Packed,
    @arg(name = "g", doc = "guard digits of the SOA's online units") g: Int = 3,
    @arg(doc = "arithmetic of the SOAs and TSAs: online (the dissertation's) or conventional (correctly rounded floating point)") arith: Arith = Arith.Online,
    @arg(doc = "full: the SOAs' arithmetic, every colour checked; timing: each SOA a latency-exact delay line, cycle-exact and faster to simulate, colours taken from the model (docs/harness.md)") fidelity: Option[Fidelity] = None,
    @arg(doc = "memory latency in cycles") latency: Int = 100,
    @arg(doc = "draw each request's latency from [latency, this] (0: fixed latency)") latencyMax: Int = 0,
    @arg(doc = "probability of a gap in the query stream each cycle") queryGap: Double = 0,
    @arg(doc = "probability that the memory refuses a request each cycle") reqStall: Double = 0,
    @arg(doc = "probability that the memory holds back a ready response beat") respGap: Double = 0,
    @arg(doc = "probability that a request's latency comes from the long tail [latency-max, tail-latency]") tailProb: Double = 0,
    @arg(doc = "longest latency of the tail, in cycles") tailLatency: Int = 0,
    @arg(doc = "memory bandwidth in bytes per cycle") bandwidth: Double = 14.0,
    @arg(doc = "clock for the GB/s figure, in GHz") clockGhz: Double = 1.5,
    @arg(doc = "seed of the memory's response reordering") seed: Long = 1,
    @arg(doc = "threads of the Verilator model (a separate build; 1 is fastest on this design, see docs/harness.md)") simThreads: Int = 1,
    @arg(doc = "stop the run after this many cycles (0: no limit): what came out is checked, the unfinished frame is not compared") maxCycles: Long = 0,
    @arg(doc = "output folder") out: String = "out",
    @arg(doc = "worker threads of the model") threads: Int = Parallel.defaultThreads,
    @arg(doc = "order in which the host runs the queries, and writes their records: host (the renderer's, pixel by pixel) or morton (along a Z-order curve through the query points, for photon locality); the frame and the (query, photon) pairs are the same, the queries numbered in that order") queryOrder: Option[QueryOrder] = None,
    hw: HwOptions = HwOptions()) {

  /** The fidelity asked for, else the command's default `default` (full for `render` and `sweep`, timing for `evaluate`). */
  def fidelityOr(default: Fidelity = Fidelity.Full): Fidelity = fidelity.getOrElse(default)

  /** The harness's options for each run, with an FST waveform of cycles [waveStart, waveEnd] when `wave` is given. */
  def harness(wave: Option[Path] = None, waveStart: Long = 0, waveEnd: Long = Long.MaxValue): Harness.RunOptions =
    Harness.RunOptions(latency, bandwidth, seed, maxCycles, clockGhz, wave, waveStart, waveEnd, latencyMax, queryGap, reqStall,
      respGap, simThreads, tailProb, tailLatency, readStream = hw.readStream.value)

  /** These options as the value a run is made from, the fidelity `default` unless `--fidelity` is
    * given and the harness's options `harness` (a waveform for `render`). */
  def settings(default: Fidelity = Fidelity.Full, harness: Option[Harness.RunOptions] = None): RunSettings =
    RunSettings(scene, format, layout, g, arith, fidelityOr(default), harness.getOrElse(this.harness()), out, threads, hw.tuning,
      queryOrder.getOrElse(RunSettings.defaultOrder(hw.tuning.hierarchy)))
}
