package mapm.pipeline

import java.nio.file.Files
import mapm.model._
import mapm.numerics._
import org.scalatest.funsuite.AnyFunSuite

/** The `model` render of the default Cornell box, end to end. */
class ModelRunSpec extends AnyFunSuite {
  test("the Cornell box renders with colour bleeding from the red and green walls") {
    val out = Files.createTempDirectory("mapm-model")
    val r = ModelRun.run(ModelRun.defaultScene, None, out.toString, threads = 2, quiet = true)
    r.files.foreach(f => assert(Files.size(f) > 0, s"$f written"))
    val json = ujson.read(Files.readString(r.files.last))
    assert(json("queries").num == r.frame.queries.length)
    assert(json("shaderOpsPassingCond").num <= json("shaderOps").num)
    assert(json("treeDepth").num == 11) // 2000 photons: ceil(log2(2001)) levels
    assert(r.psnr > 90, s"fp32 against float64: ${r.psnr} dB")

    // Pixels whose primary hit is a white surface: indirect red/green on the left (next to the red
    // wall) and on the right (next to the green wall).
    val cfg = r.frame.config
    val primary = PrimaryHits.trace(TriKdTree.build(cfg.scene), cfg.camera, cfg.width, cfg.height)
    def whitePixel(p: Int): Boolean = primary.hit(p) && cfg.scene.material(primary.triangle(p)).name == "white"
    def ratio(cols: Range): Double = {
      var red = 0.0; var green = 0.0
      for (y <- 0 until cfg.height; x <- cols) {
        val p = y * cfg.width + x
        if (whitePixel(p)) { red += r.indirect(3 * p); green += r.indirect(3 * p + 1) }
      }
      red / green
    }
    val third = cfg.width / 3
    val left = ratio(0 until third)
    val right = ratio(cfg.width - third until cfg.width)
    // The white material itself has red/green = 0.725/0.71, about 1.02.
    assert(left > 1.2, s"red bleeding on the left: red/green = $left")
    assert(right < 0.85, s"green bleeding on the right: red/green = $right")
  }

  test("a missing scene file is a one-line error") {
    val e = intercept[mapm.MapmError](ModelRun.run("no/such/scene.json", None, "out", 1, quiet = true))
    assert(e.getMessage.contains("no/such/scene.json") && !e.getMessage.contains("\n"))
  }
}
