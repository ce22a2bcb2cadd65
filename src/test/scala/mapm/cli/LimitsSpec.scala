package mapm.cli

import mapm.pipeline.Configure

import java.nio.file.{Files, Paths}

import mapm.MapmError
import mapm.numerics.{FloatFormat, NodeWord}
import mapm.params.{MapmParams, ModuleCounts}
import mapm.top.Mapm
import org.scalatest.funsuite.AnyFunSuite

/** Parameters and inputs past what the hardware can hold are one clear error before any work:
  * module counts past their range (whose largest values still size every memory port), scenes
  * with more query points or photons than the hardware's indices count. */
class LimitsSpec extends AnyFunSuite {
  private val dir = Paths.get("target/limits-test")

  private def scene(name: String, w: Int, h: Int, rays: Int, photons: Int) = {
    Files.createDirectories(dir)
    val obj = mapm.model.TestScenes.cornellObj.toAbsolutePath.toString
    Files.write(dir.resolve(s"$name.json"),
      s"""{ "obj": "$obj", "camera": { "position": [278, 273, -530], "direction": [0, 0, 1], "fov": 39.3 },
         |  "lights": [ { "type": "point", "position": [1, 25, 1], "power": [1e7, 1e7, 1e7] } ],
         |  "width": $w, "height": $h, "finalGatherRays": $rays, "photons": $photons }""".stripMargin.getBytes("UTF-8")).toString
  }

  test("a module count past its range names the option and the range") {
    val e = intercept[MapmError](EmitCommand.run(Seq("--tsm", "100000", "--out", dir.resolve("emit").toString)))
    assert(e.getMessage.contains(s"--tsm (TSM count) must be 1..${ModuleCounts.MaxTsm}, got 100000"), e.getMessage)
    for ((opt, v) <- Seq("--som" -> "0", "--soa" -> "17"))
      assert(intercept[MapmError](EmitCommand.run(Seq(opt, v))).getMessage.contains(s"$opt ("))
  }

  test("a whole MAPM past the emit limit (1024/1024/4, the largest counts the parameters take) is one line naming the limit, before any work") {
    val t0 = System.nanoTime()
    val e = intercept[MapmError](EmitCommand.run(Seq("--tsm", "1024", "--som", "1024", "--soa", "4", "--out", dir.resolve("emit-big").toString)))
    assert(e.getMessage.startsWith("1024/1024/4 has 2048 TSMs and SOMs together; whole MAPMs are emitted up to " + mapm.sim.MapmRtl.MaxEmitModules) &&
      e.getMessage.contains("--beyond-limit") && !e.getMessage.contains("\n"), e.getMessage)
    // render refuses it before the model runs, as it refuses a scene too large for the indices.
    val r = intercept[MapmError](RenderCommand.run(Seq("--scene", scene("limit", 4, 3, 1, 10), "--tsm", "300", "--som", "300", "--soa", "1",
      "--out", dir.toString)))
    assert(r.getMessage.startsWith("300/300/1 has 600 TSMs and SOMs together"), r.getMessage)
    assert((System.nanoTime() - t0) / 1e9 < 20, "refused before any work")
    // At the limit it is taken: the check passes (emitting 256/256/4 itself takes minutes: docs/mapm.md).
    mapm.sim.MapmRtl.checkEmittable(Configure.of(256, 256, 4, FloatFormat.fp32, 3))
  }

  test("at the largest counts every memory port's id still fits its 16 bits (the counts' ranges are the real limit)") {
    val p = Configure.of(ModuleCounts.MaxTsm, ModuleCounts.MaxSom, ModuleCounts.MaxSoaPerSom, FloatFormat.fp64, 3)
    val top = mapm.uncore.Shapes(p).mem // sizes the TS L2, SOQ and SOP L2 ports and the arbiters above them; throws when an id is too wide
    assert(top.idBits <= 16)
    // Past the TSM range the ids would not fit: the range guards the port, not a guess.
    val tsL1 = mapm.uncore.Shapes(p).tsL1.down.idBits
    assert(tsL1 + chisel3.util.log2Ceil(100000) > 16)
  }

  test("a scene with more query points than the 24-bit query index is refused before the model runs") {
    val s = scene("many-queries", 2000, 2000, 5, 100) // 20 M query points
    val t0 = System.nanoTime()
    val e = intercept[MapmError](RenderCommand.run(Seq("--scene", s, "--tsm", "1", "--som", "1", "--soa", "1", "--out", dir.toString)))
    assert(e.getMessage.contains("up to 20000000 query points") && e.getMessage.contains("24-bit query index (at most 16777216)"), e.getMessage)
    assert((System.nanoTime() - t0) / 1e9 < 20, "refused before any work")
  }

  test("a scene with more photons than the 22-bit node index is refused before the model runs") {
    val s = scene("many-photons", 4, 4, 1, 5000000)
    val e = intercept[MapmError](RenderCommand.run(Seq("--scene", s, "--tsm", "1", "--som", "1", "--soa", "1", "--out", dir.toString)))
    assert(e.getMessage.contains("5000000 photons exceed the hardware's 22-bit node index (at most 4194304 photons)"), e.getMessage)
    val huge = scene("too-many-photons", 4, 4, 1, Int.MaxValue)
    assert(intercept[MapmError](mapm.model.SceneConfig.load(Paths.get(huge))).getMessage
      .contains(s"must be at most ${NodeWord.MaxNodes} (the node record's index field)"))
  }
}
