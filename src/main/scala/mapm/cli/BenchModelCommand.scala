package mapm.cli

import mapm.pipeline._

import mainargs.{ParserForMethods, arg, main}
import mapm.MapmError
import mapm.model.Parallel
import mapm.numerics.FloatFormat
import Args.FloatFormatReader

/** `mapm bench-model`: the whole `model` pipeline of a scene, in process, timed.
  *
  * Runs [[ModelRun.run]] (load the scene, trace photons, primary rays and final gather, direct
  * light, choose h, build the photon tree, quantize, search and shade in the format and in float64,
  * write the images and the stats JSON) `--warmup` times untimed and then `--repeat` times, and
  * prints per run its wall and process-CPU seconds, the seconds of every stage, and the shader
  * operations per second of the format's search-and-shade stage (per wall second and per CPU
  * second of the whole process during the stage). The last line gives the fastest and the median
  * run. Issue 2's first speed target is the Table 4.8 workload (the default scene) under 10 s wall.
  */
object BenchModelCommand extends Command {
  val name = "bench-model"
  val summary = "benchmark the whole model pipeline of a scene (scene file to stats and image), per stage"

  @main
  def benchModel(
      @arg(doc = "scene description file (JSON)") scene: String = RenderCommand.defaultScene,
      @arg(doc = "timed runs (after the warm-up runs)") repeat: Int = 3,
      @arg(doc = "untimed warm-up runs first (JIT)") warmup: Int = 1,
      @arg(doc = "number format (default: the scene's, else fp32)") format: Option[FloatFormat] = None,
      @arg(doc = "output folder (every run writes its images and stats there)") out: String = "out",
      @arg(doc = "worker threads") threads: Int = Parallel.defaultThreads,
      @arg(name = "g", doc = "guard digits of the SOA's online colour chain") g: Int = 3
  ): Int = {
    MapmError.check(repeat >= 1, s"bench-model: --repeat must be at least 1, got $repeat")
    MapmError.check(warmup >= 0, s"bench-model: --warmup must be at least 0, got $warmup")
    ModelRun.loadScene(scene) // a bad scene fails before any run
    println(s"bench-model: $scene, $threads thread(s), $warmup warm-up run(s), $repeat timed run(s)")
    for (w <- 1 to warmup) {
      val t = System.nanoTime()
      ModelRun.run(scene, format, out, threads, quiet = true, g = g)
      println(f"warm-up $w: ${(System.nanoTime() - t) / 1e9}%.3f s")
    }
    val walls = for (rep <- 1 to repeat) yield {
      val c0 = ProcessCpu.seconds
      val t = System.nanoTime()
      val r = ModelRun.run(scene, format, out, threads, quiet = true, g = g)
      val wall = (System.nanoTime() - t) / 1e9
      val cpu = ProcessCpu.since(c0)
      if (rep == 1) {
        val f = r.frame
        println(s"workload: ${f.width}x${f.height}, ${f.config.finalGatherRays} final-gather rays, ${r.stats.photons} photons, " +
          s"format ${f.format} (SOA g = $g), h = ${f.map.hValue}; ${r.stats.describe}")
      }
      val so = r.stats.shaderOps.toDouble
      val searchWall = r.times.stages.collectFirst { case ("search+shade (format)", v) => v }.getOrElse(0.0)
      val searchCpu = r.searchCpuSeconds
      val rate = if (searchWall > 0) f", search+shade ${so / searchWall / 1e6}%.2f M shader ops/s" else ""
      val perCpu = searchCpu.filter(_ > 0).map(x => f" (${so / x / 1e6}%.2f M per CPU-second)").getOrElse("")
      println(f"run $rep: wall $wall%.3f s${cpu.map(x => f", CPU $x%.3f s").getOrElse("")}$rate$perCpu")
      println(r.times.stages.map { case (k, v) => f"$k $v%.3f" }.mkString("  stages (s): ", ", ", ""))
      wall
    }
    val sorted = walls.sorted
    println(f"wall: fastest ${sorted.head}%.3f s, median ${sorted(sorted.length / 2)}%.3f s over $repeat run(s)")
    0
  }

  lazy val parser: ParserForMethods[_] = ParserForMethods(this)

  def run(args: Seq[String]): Int = Args.run(this, args)
}
