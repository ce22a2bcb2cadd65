package mapm.cli

import mapm.pipeline._

import java.nio.file.{Files, Path}

import mainargs.{Flag, ParserForMethods, arg, main}
import mapm.MapmError
import mapm.cli.Args.rtlOptionsParser
import mapm.sim.{Harness, MapmRtl, Verilator}
import scala.sys.process._

/** `mapm bench-sim`: the simulation's figures of merit for one configuration on one frame
  * (docs/harness.md, "Simulation speed"):
  *  - the Verilator build time (`--fresh`: from scratch, without ccache; else whatever the cache gives);
  *  - simulated cycles per second of the whole frame, and its PASS/FAIL verdict;
  *  - callgrind's instructions per simulated cycle over cycles `--from` to `--to`: one run under
  *    `--instr-atstart=no` to cycle `--to` (`--max-cycles`), in which the harness switches the
  *    instrumentation on at cycle `--from` (`--measure-from`) and off when its cycle loop ends, so
  *    reading the image and the expected SOs, and the cycles before, are not counted, and a window
  *    deep in the frame costs little more than running to it. Unlike seconds, this count repeats
  *    on a shared machine.
  * Writes the figures to `<out>/bench-sim-<top>.json` as well. */
object BenchSimCommand extends Command {
  val name = "bench-sim"
  val summary = "benchmark: Verilator build time, simulated cycles/s and callgrind instructions per simulated cycle"

  @main
  def benchSim(
      @arg(doc = "Tree Search Modules") tsm: Int = 16,
      @arg(doc = "Shader Operation Modules") som: Int = 16,
      @arg(doc = "SOAs per SOM") soa: Int = 2,
      @arg(doc = "first cycle of the callgrind window") from: Long = 1000,
      @arg(doc = "last cycle of the callgrind window") to: Long = 3000,
      @arg(doc = "build from scratch without ccache, to measure the build") fresh: Flag,
      @arg(doc = "skip the callgrind runs") noCallgrind: Flag,
      opts: RtlOptions
  ): Int = {
    MapmError.check(from >= 0 && to > from, s"--from and --to must be 0 <= from < to, got $from and $to")
    val harness = opts.harness()
    val setup = opts.settings(harness = Some(harness)).setup(Seq((tsm, som, soa)))
    val (p, prep) = (setup.params.head, setup.prep)
    val log = (l: String) => System.err.println(s"mapm: $l")
    val built = RtlRun.build(p, trace = false, opts.simThreads, log, fresh.value)
    val (exe, top) = (built.exe, MapmRtl.topName(p))
    val outcome = Harness.run(exe, prep.image, prep.expected, prep.work, harness, Some(s"RTL ${p.counts.label}"))
    val stats = outcome.stats.getOrElse(MapmError.fail(s"bench-sim: the harness wrote no stats: ${outcome.verdict}"))
    val perCycle = if (noCallgrind.value) None else {
      val valgrind = Verilator.valgrind
      val file = prep.work.resolve(s"callgrind-$from-$to.out")
      val cmd = Seq(valgrind, "--tool=callgrind", "--instr-atstart=no", s"--callgrind-out-file=$file", exe.toString,
        "--image", prep.image.toString, "--expected", prep.expected.toString, "--out", prep.work.resolve("callgrind").toString) ++
        harness.copy(maxCycles = to).args ++ Seq("--measure-from", from.toString)
      Files.createDirectories(prep.work.resolve("callgrind"))
      log(s"callgrind over cycles $from to $to ...")
      Process(cmd).!(ProcessLogger(_ => (), _ => ()))
      Some(summary(file).toDouble / (to - from))
    }
    val build = built.buildSeconds
    println(f"$top (${p.counts.label}, ${p.numbers.format}, ${p.numbers.arith}): emit ${built.emitSeconds}%.1f s (cached when fast), " +
      f"build ${build}%.1f s${if (fresh.value) " (fresh, no ccache)" else " (cache allowed; --fresh to measure)"}")
    println(f"simulation: ${stats.cycles}%d cycles in ${stats.wallSeconds}%.1f s = ${stats.simulatedCyclesPerSecond}%.0f cycles/s; ${outcome.verdict}")
    perCycle.foreach(v => println(f"callgrind: ${v / 1e6}%.3f M instructions per simulated cycle (cycles $from to $to)"))
    val json = ujson.Obj("top" -> top, "config" -> p.counts.label, "scene" -> opts.scene, "buildSeconds" -> build,
      "freshBuild" -> fresh.value, "cycles" -> stats.cycles.toDouble, "simulatedCyclesPerSecond" -> stats.simulatedCyclesPerSecond,
      "verdict" -> outcome.verdict, "instructionsPerCycle" -> perCycle.map(ujson.Num(_)).getOrElse(ujson.Null),
      "callgrindFrom" -> from.toDouble, "callgrindTo" -> to.toDouble)
    val out = java.nio.file.Paths.get(opts.out).resolve(s"bench-sim-$top.json")
    Files.write(out, ujson.write(json, indent = 2).getBytes("UTF-8"))
    println(s"wrote $out")
    if (!outcome.passed) MapmError.fail(s"bench-sim: ${outcome.verdict}")
    0
  }

  /** The instructions a callgrind output file counted: its `totals:` line (with instrumentation
    * switched on and off by the program, its `summary:` line says 0), else its `summary:` line. */
  def summary(file: Path): Long = {
    MapmError.check(Files.isRegularFile(file), s"callgrind wrote no $file")
    val lines = scala.io.Source.fromFile(file.toFile).getLines().toSeq
    def field(key: String) = lines.find(_.startsWith(key)).map(_.stripPrefix(key).trim.split("\\s+").head.toLong)
    field("totals:").orElse(field("summary:")).getOrElse(MapmError.fail(s"$file: no callgrind totals or summary line"))
  }

  lazy val parser: ParserForMethods[_] = ParserForMethods(this)

  def run(args: Seq[String]): Int = Args.run(this, args)
}
