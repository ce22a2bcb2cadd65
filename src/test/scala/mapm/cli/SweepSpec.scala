package mapm.cli

import mapm.evaluation._

import mapm.costflow._

import mapm.Slow
import java.nio.file.{Files, Paths}

import mapm.MapmError
import org.scalatest.funsuite.AnyFunSuite

/** The sweep's configuration list, its bar charts, and sweeps of a tiny frame through the RTL:
  * without cost, with the cost flow at e5m4 and two local jobs, and with smaller caches. */
@Slow
class SweepSpec extends AnyFunSuite {
  private val dir = Paths.get("target/sweep-test")
  /** A 8x6 frame of the Cornell box, 4 rays, 200 photons: seconds per configuration. */
  lazy val tinyScene: java.nio.file.Path = {
    Files.createDirectories(dir)
    val obj = mapm.model.TestScenes.cornellObj.toAbsolutePath.toString
    Files.write(dir.resolve("tiny.json"),
      s"""{ "obj": "$obj", "camera": { "position": [278, 273, -530], "direction": [0, 0, 1], "up": [0, 1, 0], "fov": 39.3 },
         |  "lights": [ { "type": "point", "position": [1, 25, 1], "power": [10000000, 10000000, 10000000] } ],
         |  "width": 8, "height": 6, "finalGatherRays": 4, "photons": 200, "maxBounces": 3, "h": { "auto": 20 }, "seed": 3 }""".stripMargin
        .getBytes("UTF-8"))
  }
  private def verilator(): Unit = assume(mapm.testutil.HostTools.onPath("verilator"), "verilator is not on PATH")

  /** The CSV's rows as maps from column name to cell. */
  def readCsv(f: java.nio.file.Path): Seq[Map[String, String]] = {
    val lines = new String(Files.readAllBytes(f), "UTF-8").linesIterator.toSeq
    val head = lines.head.split(",", -1).toSeq
    lines.tail.map(l => head.zip(l.split(",", -1)).toMap)
  }
  private def close(a: Double, b: Double, what: String): Unit = assert(math.abs(a - b) <= 1e-5 * math.max(math.abs(a), math.abs(b)), s"$what: $a against $b")

  test("sweep 1/1/1,2/1/2 of a tiny frame through the RTL, no cost: CSV rows, speed-up, throughput at the clock, charts") {
    verilator()
    val out = dir.resolve("out")
    assert(SweepCommand.run(Seq("--configs", "1/1/1,2/1/2", "--scene", tinyScene.toString, "--out", out.toString, "--threads", "2",
      "--no-cost", "--jobs", "1", "--clock-ghz", "1.5")) == 0)
    val rows = readCsv(out.resolve("sweep-test-tiny-sweep.csv"))
    assert(rows.map(_("config")) == Seq("1/1/1", "2/1/2") && rows.forall(_("result") == "PASS"))
    assert(rows.forall(_("cycles").matches("[1-9][0-9]*")), "cycles are whole numbers, every digit kept")
    val cycles = rows.map(_("cycles").toDouble)
    assert(rows.head("speedup").toDouble == 1.0 && math.abs(rows(1)("speedup").toDouble - cycles(0) / cycles(1)) < 1e-4, "speed-up = first's cycles / own")
    for (r <- rows) {
      close(r("bso_per_s").toDouble, r("so_per_cycle").toDouble * 1.5, "billion SO/s = SO/cycle x 1.5 GHz")
      close(r("gb_per_s").toDouble, r("bytes_fetched").toDouble / r("cycles").toDouble * 1.5, "GB/s = bytes / cycles x 1.5 GHz")
      assert(r("area_mm2").isEmpty && r("power_mw").isEmpty, "no cost columns without the cost flow")
    }
    for (c <- Seq("so-per-cycle", "throughput")) assert(Files.size(out.resolve(s"sweep-test-tiny-sweep-$c.png")) > 0)
  }

  test("sweep with cost at e5m4, two jobs at once: area and power are the unit reports' figures times the counts, at fmax") {
    verilator()
    val out = dir.resolve("out-cost")
    assert(SweepCommand.run(Seq("--configs", "1/1/1,2/1/2", "--scene", tinyScene.toString, "--out", out.toString, "--threads", "2",
      "--format", "5,4", "--jobs", "2")) == 0)
    val rows = readCsv(out.resolve("sweep-test-tiny-sweep.csv"))
    assert(rows.map(_("config")) == Seq("1/1/1", "2/1/2") && rows.forall(_("result") == "PASS"))
    // the unit reports the sweep used (the cache finds them without running the flow again), read
    // here from the cost flow's own cost.json files
    def report(unit: String) = {
      val f = UnitCostCache.get(unit, mapm.numerics.FloatFormat(5, 4), 3, mapm.numerics.Arith.Online, l => fail(s"ran the flow again: $l")).file
      ujson.read(Files.readAllBytes(f))
    }
    val (soa, tsa) = (report("soa"), report("tsa"))
    assert(soa("top").str == "SOA_e5m4_g3" && tsa("top").str == "TSA_e5m4_t16")
    val clock = math.min(soa("fmaxGHz").num, tsa("fmaxGHz").num)
    for (r <- rows) {
      val (t, nSoa) = (r("tsm").toInt, r("som").toInt * r("soa").toInt)
      close(r("clock_ghz").toDouble, clock, "clock = the slower unit's fmax")
      close(r("area_mm2").toDouble, (nSoa * soa("areaUm2").num + t * tsa("areaUm2").num) / 1e6, "area")
      def mw(u: ujson.Value) = u("atFmax")("dynamicPjPerCycle").num * clock + u("atFmax")("leakagePowerMw").num
      close(r("power_mw").toDouble, nSoa * mw(soa) + t * mw(tsa), "power")
      close(r("mso_per_s_per_mm2").toDouble, r("bso_per_s").toDouble * 1000 / r("area_mm2").toDouble, "MSO/s/mm^2")
      close(r("bso_per_s_per_w").toDouble, r("bso_per_s").toDouble / (r("power_mw").toDouble / 1000), "BSO/s/W")
    }
    for (c <- Seq("so-per-cycle", "throughput", "per-area", "per-power")) assert(Files.size(out.resolve(s"sweep-test-tiny-sweep-$c.png")) > 0)
  }

  test("render and sweep take the cache and queue sizes: smaller L1s miss more, and the frame still passes") {
    verilator()
    val out = dir.resolve("out-tuned")
    val args = Seq("--configs", "1/1/1", "--scene", tinyScene.toString, "--threads", "2", "--no-cost")
    assert(SweepCommand.run(args ++ Seq("--out", out.resolve("default").toString)) == 0)
    assert(SweepCommand.run(args ++ Seq("--out", out.resolve("small").toString, "--ts-l1", "512/32/1", "--sop-l1", "1K/32/1",
      "--rs-entries", "16", "--rq-depth", "64", "--mem-outstanding", "8")) == 0)
    val Seq(d) = readCsv(out.resolve("default/sweep-test-tiny-sweep.csv"))
    val Seq(s) = readCsv(out.resolve("small/sweep-test-tiny-sweep.csv"))
    assert(s("result") == "PASS")
    assert(s("hit_rate_tsL1").toDouble < d("hit_rate_tsL1").toDouble && s("hit_rate_sopL1").toDouble < d("hit_rate_sopL1").toDouble,
      s"TS L1 ${s("hit_rate_tsL1")} against ${d("hit_rate_tsL1")}, SOP L1 ${s("hit_rate_sopL1")} against ${d("hit_rate_sopL1")}")
    val stats = ujson.read(Files.readAllBytes(out.resolve("small/sweep-test-tiny-rtl/sweep-1-1-1/stats.json")))
    info(s"default: TS L1 ${d("hit_rate_tsL1")}, SOP L1 ${d("hit_rate_sopL1")}, ${d("cycles")} cycles; small: ${s("hit_rate_tsL1")}, ${s("hit_rate_sopL1")}, ${s("cycles")} cycles")
    assert(stats("top").str.startsWith("Mapm_t1s1a1"))
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

  test("grouped bar chart: one colour per TSM count, bars in proportion across groups") {
    val path = Paths.get("target/sweep-test/grouped.png")
    BarChart.write(path, "Throughput", "BSO/s", Seq("1/1/2" -> 1.0, "1/1/3" -> 2.0, "2/1/2" -> 3.0), l => s"${l.takeWhile(_ != '/')} TSM")
    val img = javax.imageio.ImageIO.read(path.toFile)
    def height(c: java.awt.Color) = (0 until img.getWidth).map(x => (0 until img.getHeight).count(y => img.getRGB(x, y) == c.getRGB)).max
    val (a, b) = (height(BarChart.GroupColors(0)), height(BarChart.GroupColors(1)))
    assert(a > 0 && b > 0, "both groups drawn in their own colours")
    // the first group's tallest bar is 2.0, the second's 3.0 (the legend's small swatches are shorter than either)
    assert(math.abs(a / b.toDouble - 2.0 / 3.0) < 0.03, s"heights $a and $b")
  }
}

