package mapm.cli

import mapm.pipeline.Stress

import java.nio.file.Paths

import mainargs.{ParserForMethods, arg, main}
import mapm.MapmError
import mapm.model.Parallel
import mapm.numerics.FloatFormat
import Args.SoBusReader

/** `mapm stress`: the whole MAPM's RTL under many random memory systems. For each configuration
  * (TSM/SOM/SOA, optionally `:format`) and each seed, the harness runs a small frame with the
  * memory behaviour the seed draws ([[Stress.draw]]): base and random latency, a long
  * latency tail, response reordering (the harness's DRAM, seeded), refused requests, response gaps,
  * query-stream gaps and bandwidth. Every run is checked as `render` checks it: every shader
  * operation bit-exact against the model (none lost, none duplicated, none unexpected), the frame
  * bit-equal, the TS-op and SO counters equal to the model's.
  *
  * Each configuration is verilated once. Stops at the first failing run and prints the `render`
  * command that reproduces it, with a waveform window ending at the failure. Exit 0 only when every
  * run passed. Writes `stress.csv` (one row per run) into `--out`. */
object StressCommand extends Command {
  val name = "stress"
  val summary = "run the RTL over many seeds of random memory latency, reordering and stalls; check every run"
  val defaultScene = "test-scenes/cornell-box/scene-small.json"
  val defaultConfigs = "1/1/1,2/1/2,4/4/2,3/2/3,2/2/2:fp16"

  /** "1/1/1,2/2/2:fp16" into entries; a [[MapmError]] naming a bad one. */
  def parseEntries(s: String): Seq[Stress.Entry] =
    s.split(',').map(_.trim).filter(_.nonEmpty).toSeq.map { e =>
      val (counts, fmt) = e.split(':') match {
        case Array(c) => (c, None)
        case Array(c, f) => (c, Some(FloatFormat.parse(f)))
        case _ => MapmError.fail(s"stress: --configs entry '$e' is not TSM/SOM/SOA or TSM/SOM/SOA:FORMAT")
      }
      val (t, m, a) = SweepCommand.parseConfigs(counts).headOption.getOrElse(MapmError.fail(s"stress: empty --configs entry '$e'"))
      Stress.Entry(t, m, a, fmt)
    }

  @main
  def stress(
      @arg(doc = "seeds per configuration") seeds: Int = 100,
      @arg(doc = "first seed (seeds run first-seed, first-seed+1, ...)") firstSeed: Long = 1,
      @arg(doc = "configurations TSM/SOM/SOA or TSM/SOM/SOA:FORMAT, comma separated") configs: String = defaultConfigs,
      @arg(doc = "scene description file (JSON); small: every seed is a whole frame") scene: String = defaultScene,
      @arg(name = "g", doc = "guard digits of the SOA's online units") g: Int = 3,
      @arg(doc = "fail a run that has not finished after this many cycles") maxCycles: Long = 5000000,
      @arg(doc = "output folder") out: String = "out",
      @arg(doc = "worker threads of the model") threads: Int = Parallel.defaultThreads,
      @arg(name = "sop-l2-banks", doc = "SOP L2 banks of every configuration: 1 is one shared cache (Table 4.2's), 2 .. 64 address-interleaved banks (docs/uncore.md)") sopL2Banks: Option[Int] = None,
      @arg(doc = "stress the coprocessor (docs/coprocessor.md): its frame buffer must equal the model's in every run") coproc: mainargs.Flag = mainargs.Flag(),
      @arg(name = "so-bus", doc = "Data bus of every configuration: ring or serial (docs/mapm.md)") soBus: Option[mapm.params.SoBus] = None
  ): Int = {
    MapmError.check(seeds >= 1 && seeds <= 1000000, s"stress: --seeds must be 1..1000000, got $seeds")
    MapmError.check(firstSeed >= 0, s"stress: --first-seed must be at least 0, got $firstSeed")
    MapmError.check(maxCycles >= 1000, s"stress: --max-cycles must be at least 1000, got $maxCycles")
    val entries = parseEntries(configs)
    MapmError.check(entries.nonEmpty, "stress: no configurations given")
    sopL2Banks.foreach(mapm.pipeline.Configure.l2Structure("sop-l2-banks", _)) // a bad count fails before any work
    val tuning = mapm.pipeline.Tuning(sopL2Banks = sopL2Banks, coproc = coproc.value, soBus = soBus)
    Stress.run(scene, entries, g, seeds, firstSeed, maxCycles, Paths.get(out), threads, tuning)
    0
  }

  lazy val parser: ParserForMethods[_] = ParserForMethods(this)

  def run(args: Seq[String]): Int = Args.run(this, args)
}
