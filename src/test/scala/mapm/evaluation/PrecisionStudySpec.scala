package mapm.evaluation

import java.nio.file.{Files, Path, Paths}

import mapm.MapmError
import mapm.costflow.UnitCostCache
import mapm.model.{ImageIO, RgbImage}
import mapm.numerics.{Arith, FloatFormat, Vec3}
import org.scalatest.funsuite.AnyFunSuite

/** The precision study's own logic (the Pareto front, the recommendation, the CSV) and the FLIP
  * tool it calls, against references of this spec's own. */
class PrecisionStudySpec extends AnyFunSuite {
  /** The front by a sweep: sorted by cost (ties by error), a point is on it when its error is below
    * every error of a lower or equal cost before it, or it equals the best so far at the same cost. */
  private def sweepFront(ps: Seq[(Double, Double)]): Set[(Double, Double)] = {
    var best = Double.PositiveInfinity
    var front = Set.empty[(Double, Double)]
    for ((c, e) <- ps.sortBy(identity) if e < best) { front += ((c, e)); best = e }
    // A point equal to one on the front is on it too (neither dominates the other).
    ps.filter(front).toSet
  }

  test("the Pareto front: every set of up to 6 points on a 3 x 3 grid, against a sweep by cost") {
    val grid = for (c <- 0 to 2; e <- 0 to 2) yield (c.toDouble, e.toDouble)
    var sets = 0
    for (n <- 1 to 6; ps <- grid.combinations(n)) {
      val flags = PrecisionStudy.paretoFront(ps)
      assert(ps.zip(flags).filter(_._2).map(_._1).toSet == sweepFront(ps), ps.toString)
      sets += 1
    }
    assert(sets == (1 to 6).map(k => (1 to k).foldLeft(BigInt(1))((a, i) => a * (9 - i + 1) / i)).sum.toInt)
  }

  private def figures(unit: String, area: Double, nj: Double, fmax: Double) =
    UnitCostCache.Figures(unit, s"${unit.toUpperCase}_x", fmax, area, nj * 500, 0.01, "test", Paths.get("none"), nj)

  private def row(f: FloatFormat, a: Arith, flip: Double, soaNj: Double, tsaNj: Double = 0.1) =
    PrecisionStudy.Row(PrecisionStudy.Point(f, a, 3), 50.0, flip, PrecisionStudy.LevelDiff(if (flip < 0.03) 1 else 4, 0.1), 1000, 500, figures("soa", 1e6, soaNj, 0.3),
      figures("tsa", 5e4, tsaNj, 0.6), Some("16/16/2"), Some(400000L))

  test("a row's energy per shader operation is the SOA's plus the TSA's per tree-search operation; the frame time at the slower unit") {
    val r = row(FloatFormat.fp16, Arith.Online, 0.01, soaNj = 2.0, tsaNj = 0.4)
    assert(r.arithNjPerSo == 2.0 + 0.4 * 500 / 1000.0)
    assert(r.clockGHz == 0.3 && r.frameMs.contains(400000 / 0.3 / 1e6))
  }

  test("the recommendation: the narrowest format the criterion accepts, its cheapest row") {
    val rows = Seq(row(FloatFormat.fp32, Arith.Online, 0.001, 7.0), row(FloatFormat.fp16, Arith.Online, 0.02, 3.0),
      row(FloatFormat.fp16, Arith.Conventional, 0.02, 2.5), row(FloatFormat(5, 7), Arith.Online, 0.08, 2.0),
      row(FloatFormat.bf16, Arith.Online, 0.05, 2.2))
    val pick = PrecisionStudy.recommend(rows, _.flip <= 0.03)
    assert(pick.map(r => (r.point.format, r.point.arith)).contains((FloatFormat.fp16, Arith.Conventional)))
    assert(PrecisionStudy.recommend(rows, _.flip <= 0.0001).isEmpty)
    val csv = PrecisionStudy.csv(rows).linesIterator.toSeq
    assert(csv.size == 6 && csv.head.startsWith("point,format,bits,arith,g,psnr_db,flip"))
    // Costs (SOA + TSA x 0.5): fp32 7.05, fp16 online 3.05, fp16 conventional 2.55, e5m7 2.05, bf16 2.25. On the front: e5m7
    // (the cheapest), bf16 (dearer than e5m7, better), fp16 conventional, fp32; not fp16 online (fp16 conventional is as
    // good and cheaper).
    val onFront = csv.tail.filter(_.endsWith(",true")).map(_.split(',')(0)).toSet
    assert(onFront == Set("e5m7-online-g3", "bf16-online-g3", "fp16-conventional", "fp32-online-g3"), onFront.toString)
  }

  test("levels off: the largest channel difference and the share of pixels that differ, from PNGs written here") {
    val dir = Files.createTempDirectory("mapm-levels")
    def write(name: String, rgb: (Int, Int) => Int): Path = {
      val img = new java.awt.image.BufferedImage(5, 4, java.awt.image.BufferedImage.TYPE_INT_RGB)
      for (y <- 0 until 4; x <- 0 until 5) img.setRGB(x, y, rgb(x, y))
      val p = dir.resolve(name); javax.imageio.ImageIO.write(img, "png", p.toFile); p
    }
    val a = write("a.png", (x, y) => (x * 40) << 16 | (y * 50) << 8 | 7)
    val b = write("b.png", (x, y) => if (x == 2 && y == 1) (x * 40) << 16 | (y * 50 + 3) << 8 | 7 else if (x == 4 && y == 3) (x * 40 - 1) << 16 | (y * 50) << 8 | 7 else (x * 40) << 16 | (y * 50) << 8 | 7)
    assert(PrecisionStudy.levelDiff(a, a) == PrecisionStudy.LevelDiff(0, 0.0))
    val d = PrecisionStudy.levelDiff(a, b)
    assert(d.maxLevels == 3 && d.pixelsDiffering == 2.0 / 20 && !d.lossless && PrecisionStudy.LevelDiff(1, 0.5).lossless)
    val c = write("c.png", (_, _) => 0)
    val small = dir.resolve("small.png")
    javax.imageio.ImageIO.write(new java.awt.image.BufferedImage(2, 2, java.awt.image.BufferedImage.TYPE_INT_RGB), "png", small.toFile)
    assert(intercept[MapmError](PrecisionStudy.levelDiff(c, small)).getMessage.contains("2x2"))
  }

  private def png(dir: Path, name: String, f: (Int, Int) => Vec3): Path = {
    val p = dir.resolve(name)
    ImageIO.writePng(p, RgbImage(32, 24, Array.tabulate(32 * 24)(i => f(i % 32, i / 32))))
    p
  }

  test("FLIP: 0 for the same image, more for a larger change, and a one-line error for images of two sizes") {
    val dir = Files.createTempDirectory("mapm-flip-spec")
    val base = png(dir, "base.png", (x, y) => Vec3(x / 40.0, y / 30.0, 0.3))
    val small = png(dir, "small.png", (x, y) => Vec3(x / 40.0, y / 30.0, if (x == 5 && y == 5) 0.35 else 0.3))
    val large = png(dir, "large.png", (x, y) => Vec3(x / 40.0, y / 30.0, if (x < 16) 0.9 else 0.3))
    assert(Flip.meanError(base, base) == 0.0)
    val (a, b) = (Flip.meanError(base, small), Flip.meanError(base, large))
    assert(a > 0 && a < b && b < 1, s"one pixel $a, half the image $b")
    val other = dir.resolve("other.png")
    ImageIO.writePng(other, RgbImage(8, 8, Array.fill(64)(Vec3(0.5, 0.5, 0.5))))
    val e = intercept[MapmError](Flip.meanError(base, other))
    assert(e.getMessage.startsWith("FLIP failed") && !e.getMessage.contains("\n"), e.getMessage)
  }
}
