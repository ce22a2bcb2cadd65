package mapm.costflow

import java.nio.file.{Files, Path}

import mapm.MapmError
import mapm.cost.UnitCost
import mapm.format.SlotLayout
import mapm.model.Parallel
import mapm.numerics.{Arith, FloatFormat}
import mapm.params.Fidelity
import mapm.pipeline.{Configure, RtlRun, RunSettings, Tuning}
import mapm.sim.Harness

/** What `mapm cost` measures, each an entry point that runs the flow, prints its table and writes
  * its reports under `out`: one unit ([[unit]]), one unit in both arithmetics ([[compareUnits]]),
  * a whole MAPM configuration ([[config]]), and both MAPMs rendering a scene ([[compareSystems]]).
  *
  * @param format    float format of the units
  * @param g         guard digits of the SOA's online units
  * @param fpuWeight logic per pipeline stage of the conventional FP units
  * @param lib       Liberty file (None: OSU 0.18 um)
  * @param clocks    target clocks in GHz
  * @param abc       ABC script: plain, buffer or both
  * @param ops       operations of the gate-level simulation
  * @param fromFrame whether the operations come from `scene`'s frame (else seeded random ones)
  * @param scene     the scene whose operations drive the simulation, and which the MAPMs render
  * @param seed      seed of the valid pattern and of random operations
  * @param out       output folder
  * @param tuning    the memory hierarchy and sizes of the whole MAPMs it costs or renders
  */
final case class CostRun(format: FloatFormat, g: Int, fpuWeight: Double, lib: Option[Path], clocks: Seq[Double], abc: String,
                         ops: Int, fromFrame: Boolean, scene: String, seed: Long, out: Path, tuning: Tuning = Tuning()) {
  private lazy val frameOps = CostFlow.frame(scene, format)
  private def log(s: String): Unit = System.err.println(s"cost: $s")

  /** Unit `u` in arithmetic `a`, its reports into `dir` (default: the output folder). */
  def unit(u: String, a: Arith, dir: Path = out): UnitCost = {
    val cu = CostUnits(u, format, g, fpuWeight, a, tuning.soaStageGate)
    val useFrame = fromFrame && cu.checksModel
    val source = if (useFrame) s"SOs/TS ops of $scene"
      else if (cu.checksModel) s"random operations (seed $seed)" else s"random digit streams (seed $seed)"
    val r = CostFlow(lib, clocks, abc, dir).unit(cu, format, if (Seq("soa", "mul", "div").contains(u) && a == Arith.Online) Some(g) else None,
      CostUnits.ops(cu, format, g, if (useFrame) Some(frameOps) else None, ops, seed, a), seed, source)
    print(r.markdown)
    println(s"wrote ${dir.resolve("cost.json")} and cost.md")
    r
  }

  /** Unit `u` (soa or tsa) in both arithmetics, compared ([[CostCompare]]; compare.json). */
  def compareUnits(u: String): CostCompare = {
    val costs = Arith.all.map(a => unit(u, a, out.resolve(a.name)))
    val c = CostCompare(u, format, costs(0), costs(1), CostUnits(u, format, g, fpuWeight).validRate)
    println(); print(c.markdown)
    c.write(out)
    println(s"wrote ${out.resolve("compare.json")} and compare.md")
    c
  }

  /** The whole MAPM `counts` (TSM/SOM/SOA) in arithmetic `arith` ([[ConfigCost]]): its SOA and TSA
    * through the flow, then the configuration; cost.json and cost.md. */
  def config(counts: (Int, Int, Int), arith: Arith, frameStats: Option[Path] = None): ujson.Obj = {
    val base0 = Configure.of(counts._1, counts._2, counts._3, format, g, arith = arith, tuning = tuning)
    val params = base0.copy(numbers = base0.numbers.copy(fpuStageWeight = fpuWeight))
    val rendered = frameStats.map(ConfigCost.frame(_, params)) // checked before the long runs
    val frame = if (fromFrame) Some(frameOps) else None
    val source = if (fromFrame) s"SOs/TS ops of $scene" else s"random (seed $seed)"
    val units = Seq("soa", "tsa").map { k =>
      val cu = CostUnits(k, format, g, fpuWeight, arith, tuning.soaStageGate)
      log(s"unit $k ...")
      val (r, gl) = CostFlow(lib, clocks, abc, out.resolve(k)).unitWithActivity(cu, format, if (k == "soa" && arith == Arith.Online) Some(g) else None,
        CostUnits.ops(cu, format, g, frame, ops, seed, arith), seed, source)
      print(r.markdown + "\n")
      (r, gl)
    }
    val j = ConfigCost.run(CostFlow(lib, clocks, abc, out.resolve("config")), params, units(0)._1, units(1)._1, units(0)._2.meanActivity,
      out.resolve("config"), log, rendered)
    Files.createDirectories(out)
    Files.write(out.resolve("cost.json"), ujson.write(j, indent = 2).getBytes("UTF-8"))
    val md = ConfigCost.markdown(j)
    Files.write(out.resolve("cost.md"), md.getBytes("UTF-8"))
    print(md)
    println(s"wrote ${out.resolve("cost.json")} and cost.md")
    ConfigCost.boundaryViolations(j).headOption.foreach(v => mapm.MapmError.fail(s"cost: $v (cost.json, methodB.boundaries)"))
    j
  }

  /** Both arithmetics' MAPM `counts`: their SOA and TSA through the flow, and each MAPM rendering
    * the scene through the RTL ([[SystemCompare]]; compare-system.json). Fails when a render
    * failed its checks. */
  def compareSystems(counts: (Int, Int, Int)): SystemCompare = {
    val label = s"${counts._1}/${counts._2}/${counts._3}"
    val figures = Arith.all.map { a =>
      val dir = out.resolve(a.name)
      val (soaCost, tsaCost) = (unit("soa", a, dir.resolve("soa")), unit("tsa", a, dir.resolve("tsa")))
      log(s"rendering $scene through the $a $label MAPM ...")
      val settings = RunSettings(scene, Some(format), SlotLayout.Packed, g, a, Fidelity.Full, Harness.RunOptions(), dir.toString,
        Parallel.defaultThreads, tuning)
      val RtlRun.Setup(Seq(p), prep) = settings.setup(Seq(counts))
      val run = RtlRun.runConfig(prep, p, settings.harness, prep.work, l => System.err.println(s"mapm: $l"))
      val s = run.outcome.stats.getOrElse(MapmError.fail(s"cost: the $a render wrote no statistics (${run.failure})"))
      val rgb = run.outcome.frame.getOrElse(MapmError.fail(s"cost: the $a render wrote no frame"))
      SystemFigures(a, mapm.sim.MapmRtl.topName(p), s.cycles, s.soIssued, p.counts.som * p.counts.soaPerSom, p.counts.tsm,
        soaCost, tsaCost, mapm.model.Metrics.psnr(rgb, RtlRun.reference(prep, settings.threads)), run.passed)
    }
    val c = SystemCompare(label, format, scene, figures(0), figures(1))
    println(); print(c.markdown)
    c.write(out)
    println(s"wrote ${out.resolve("compare-system.json")} and compare-system.md")
    if (!figures.forall(_.passed)) MapmError.fail("cost: a render failed its checks (see above)")
    c
  }
}

object CostRun {
  /** The stimulus sources `--stimulus` takes. */
  val Stimuli: Seq[String] = Seq("frame", "random")
}
