package mapm.cli

import mapm.pipeline._

import mainargs.{ParserForMethods, arg, main}
import mapm.MapmError
import mapm.model._
import mapm.numerics._
import Args.FloatFormatReader

/** `mapm bench-search`: speed of the model's tree search + shading on a synthetic workload.
  *
  * Photons and queries are uniform in a cube; h is chosen so that the cube of side 2h around a
  * query holds about 0.55 x `--so-per-query` photons, which gives roughly `--so-per-query` shader
  * operations per query (the search also issues SOs for nodes and leaves outside that cube).
  * Shading is [[ShadeArith.rounded]] in `--format`. Prints the workload, then, after `--warmup`
  * untimed runs, per repetition the shader operations and tree-search operations per second of
  * [[Render.run]] (search, cond, three colour channels, accumulation) per wall second and per
  * process-CPU second, and last the best and the median rate. Issue 2's target is 25 million
  * shader operations per second on 2 cores.
  */
object BenchSearchCommand extends Command {
  val name = "bench-search"
  val summary = "benchmark the model's tree search and shading (shader ops per second)"

  @main
  def benchSearch(
      @arg(doc = "number of photons") photons: Int = 200000,
      @arg(doc = "number of queries") queries: Int = 100000,
      @arg(doc = "target shader operations per query (sets h)") soPerQuery: Double = 100,
      @arg(doc = "float format of the data and shading arithmetic") format: FloatFormat = FloatFormat.fp32,
      @arg(doc = "worker threads") threads: Int = 2,
      @arg(doc = "timed repetitions (after the warm-up runs)") repeat: Int = 3,
      @arg(doc = "untimed warm-up runs first (JIT)") warmup: Int = 2,
      @arg(doc = "random seed") seed: Long = 1
  ): Int = {
    Args.checkSeed(seed)
    MapmError.check(photons >= 1 && queries >= 1, "bench-search: --photons and --queries must be at least 1")
    MapmError.check(soPerQuery > 0, "bench-search: --so-per-query must be positive")
    MapmError.check(repeat >= 1, "bench-search: --repeat must be at least 1")
    MapmError.check(warmup >= 0, "bench-search: --warmup must be at least 0")
    val side = 100.0
    val rnd = new scala.util.Random(seed)
    def pt() = Vec3(rnd.nextDouble() * side, rnd.nextDouble() * side, rnd.nextDouble() * side)
    val ph = Array.fill(photons)(Photon(pt(), Vec3(rnd.nextDouble(), rnd.nextDouble(), rnd.nextDouble()), Vec3(0, -1, 0), Vec3(0, 1, 0)))
    val pixels = 4096
    val qs = Array.fill(queries)(QueryPoint(pt(), rnd.nextInt(pixels), Vec3(rnd.nextDouble(), rnd.nextDouble(), rnd.nextDouble()), Vec3(0, 1, 0)))
    val h = 0.5 * side * math.cbrt(0.55 * soPerQuery / photons)
    val t0 = System.nanoTime()
    val map = PhotonMap.build(ph, Box(Vec3.zero, Vec3(side, side, side)), format, h)
    val qset = QuerySet.build(qs, format)
    val arith = ShadeArith.rounded(format)
    println(f"workload: $photons photons, $queries queries, h = $h%.4g, format $format, $threads thread(s); build ${(System.nanoTime() - t0) / 1e9}%.2f s")
    for (_ <- 1 to warmup) Render.run(map, qset, pixels, arith, threads) // JIT
    val rates = for (rep <- 1 to repeat) yield {
      val t = System.nanoTime()
      val c = ProcessCpu.seconds
      val r = Render.run(map, qset, pixels, arith, threads)
      val s = (System.nanoTime() - t) / 1e9
      val cpu = ProcessCpu.since(c)
      val st = r.stats
      if (rep == 1) println(s"stats: ${st.describe}; ${f"${st.shaderOps.toDouble / queries}%.1f"} shader ops per query")
      // CPU time shows what the run gets when other processes share the cores
      val perCpu = cpu.map(x => f", CPU $x%.3f s: ${st.shaderOps / x / 1e6}%.1f M shader ops per CPU-second").getOrElse("")
      println(f"run $rep: $s%.3f s, ${st.shaderOps / s / 1e6}%.1f M shader ops/s, ${st.treeSearchOps / s / 1e6}%.1f M TS ops/s$perCpu")
      st.shaderOps / s
    }
    val sorted = rates.sorted
    println(f"shader ops/s: best ${sorted.last / 1e6}%.1f M, median ${sorted(sorted.length / 2) / 1e6}%.1f M over $repeat run(s)")
    0
  }

  lazy val parser: ParserForMethods[_] = ParserForMethods(this)

  def run(args: Seq[String]): Int = Args.run(this, args)
}
