package mapm.cli

import mapm.Slow
import java.nio.file.{Files, Paths}

import mapm.MapmError
import org.scalatest.funsuite.AnyFunSuite

/** The sweep's configuration list, its bar charts, and a two-configuration sweep of a tiny frame
  * through the RTL (the builds RtlRenderSpec also uses). */
@Slow
class SweepSpec extends AnyFunSuite {
  test("sweep 1/1/1,2/1/2 of a tiny frame through the RTL: CSV rows, speed-up, charts") {
    assume(mapm.testutil.HostTools.onPath("verilator"),
      "verilator is not on PATH")
    val dir = Paths.get("target/sweep-test")
    Files.createDirectories(dir)
    val obj = mapm.model.TestScenes.cornellObj.toAbsolutePath.toString
    val scene = Files.write(dir.resolve("tiny.json"),
      s"""{ "obj": "$obj", "camera": { "position": [278, 273, -530], "direction": [0, 0, 1], "up": [0, 1, 0], "fov": 39.3 },
         |  "lights": [ { "type": "point", "position": [1, 25, 1], "power": [10000000, 10000000, 10000000] } ],
         |  "width": 8, "height": 6, "finalGatherRays": 4, "photons": 200, "maxBounces": 3, "h": { "auto": 20 }, "seed": 3 }""".stripMargin
        .getBytes("UTF-8"))
    val out = dir.resolve("out")
    assert(SweepCommand.sweep(configs = Some("1/1/1,2/1/2"), opts = RtlOptions(scene = scene.toString, out = out.toString, threads = 2)) == 0)
    val lines = new String(Files.readAllBytes(out.resolve("sweep-test-tiny-sweep.csv")), "UTF-8").linesIterator.toSeq
    assert(lines.size == 3 && lines.head.startsWith("config,tsm,som,soa,cycles,so_per_cycle"))
    val rows = lines.tail.map(_.split(",", -1))
    assert(rows.map(_(0)) == Seq("1/1/1", "2/1/2") && rows.forall(_.last == "PASS"))
    assert(rows.forall(_(4).matches("[1-9][0-9]*")), "cycles are whole numbers, every digit kept")
    val cycles = rows.map(_(4).toDouble)
    assert(rows.head(7).toDouble == 1.0 && math.abs(rows(1)(7).toDouble - cycles(0) / cycles(1)) < 1e-4, "speed-up = first's cycles / own")
    assert(Files.size(out.resolve("sweep-test-tiny-sweep-so-per-cycle.png")) > 0 && Files.size(out.resolve("sweep-test-tiny-sweep-speedup.png")) > 0)
  }

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
    // bars: runs of columns holding bar-coloured pixels, left to right; a bar's height is the
    // largest span of them in one of its columns (its value label sits inside the bar)
    val bar = BarChart.BarColor.getRGB
    val columns = (0 until img.getWidth).map { x =>
      val ys = (0 until img.getHeight).filter(y => img.getRGB(x, y) == bar)
      if (ys.isEmpty) 0 else ys.last - ys.head + 1
    }
    val runs = columns.indices.filter(columns(_) > 0).foldLeft(Vector.empty[Vector[Int]]) {
      case (rs, x) if rs.nonEmpty && rs.last.last == x - 1 => rs.init :+ (rs.last :+ x)
      case (rs, x) => rs :+ Vector(x)
    }
    val heights = runs.map(_.map(columns).max)
    assert(heights.size == 3, s"a missing value draws no bar: $heights")
    // in proportion within 2 pixels, against the tallest bar (the least rounded)
    assert(heights(0) > 0 && math.abs(heights(1) - heights(2) / 2.0) <= 2 && math.abs(heights(0) - heights(2) / 4.0) <= 2, heights.toString)
    Files.deleteIfExists(path)
    BarChart.write(path, "t", "y", bars) // kept for a look: target/sweep-test/chart.png
  }
}
