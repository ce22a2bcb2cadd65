package mapm.cli

import java.nio.file.{Files, Paths}

import mapm.MapmError
import org.scalatest.funsuite.AnyFunSuite

/** The sweep's configuration list and its bar charts (the RTL runs themselves are covered by
  * RtlRenderSpec). */
class SweepSpec extends AnyFunSuite {
  test("configuration lists parse, bad entries are one clear error") {
    assert(SweepCommand.parseConfigs("1/1/2, 16/16/3,") == Seq((1, 1, 2), (16, 16, 3)))
    val e = intercept[MapmError](SweepCommand.parseConfigs("1/1/2,4/x/2"))
    assert(e.getMessage == "sweep: --configs entry '4/x/2' is not TSM/SOM/SOA (e.g. 16/16/2)")
  }

  test("bar chart: one bar per configuration, heights in proportion") {
    val path = Paths.get("target/sweep-test/chart.png")
    val bars = Seq("1/1/2" -> 1.0, "2/1/2" -> 2.0, "4/4/2" -> 4.0, "8/8/2" -> Double.NaN)
    BarChart.write(path, "Speed-up", "speed-up", bars)
    val img = javax.imageio.ImageIO.read(path.toFile)
    assert(img.getWidth == 640 && img.getHeight == 480)
    val bar = new java.awt.Color(70, 110, 170).getRGB
    // bar columns: count the bar-coloured pixels in each slot's centre column
    val slot = (640 - 80 - 20) / 4.0
    val heights = (0 until 4).map { i =>
      val x = (80 + i * slot + slot / 2).toInt
      (0 until 480).count(y => img.getRGB(x, y) == bar)
    }
    assert(heights(3) == 0, "a missing value draws no bar")
    assert(heights(0) > 0 && math.abs(heights(1) - 2 * heights(0)) <= 2 && math.abs(heights(2) - 4 * heights(0)) <= 2, heights.toString)
    Files.deleteIfExists(path)
    BarChart.write(path, "t", "y", bars) // kept for a look: target/sweep-test/chart.png
  }
}
