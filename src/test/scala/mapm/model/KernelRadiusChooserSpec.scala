package mapm.model

import mapm.numerics._

import mapm.MapmError
import org.scalatest.funsuite.AnyFunSuite

class KernelRadiusChooserSpec extends AnyFunSuite {
  private def randomPoints(n: Int, seed: Int): Array[Vec3] = {
    val r = new scala.util.Random(seed)
    Array.fill(n)(Vec3(r.nextDouble() * 100, r.nextDouble() * 50, r.nextDouble() * 80))
  }

  /** Brute force: average over the queries of the photons strictly within h. */
  private def averageWithin(ph: Array[Vec3], qs: Array[Vec3], h: Double): Double =
    qs.map(q => ph.count(p => { val d = p - q; d.dot(d) < h * h })).sum.toDouble / qs.length

  test("auto h is the smallest radius at which the average query finds the target (brute force)") {
    val ph = randomPoints(3000, 1)
    val photons = ph.map(p => Photon(p, Vec3.one, Vec3(0, -1, 0), Vec3(0, 1, 0)))
    val qs = randomPoints(500, 2)
    val queries = qs.zipWithIndex.map { case (q, i) => QueryPoint(q, i, Vec3.one, Vec3(0, 1, 0)) }
    val box = Box(Vec3.zero, Vec3(100, 50, 80))
    for (target <- Seq(1.0, 7.5, 40.0, 300.0)) {
      val h = KernelRadiusChooser.choose(photons, box, queries, target)
      assert(averageWithin(ph, qs, h) >= target, s"target $target, h $h")
      assert(averageWithin(ph, qs, h / (1 + 2e-4)) < target, s"target $target: a smaller h would do")
    }
  }

  test("impossible targets and empty inputs are clear errors") {
    val photons = Array(Photon(Vec3(1, 1, 1), Vec3.one, Vec3(0, -1, 0), Vec3(0, 1, 0)))
    val queries = Array(QueryPoint(Vec3(1, 1, 1), 0, Vec3.one, Vec3(0, 1, 0)))
    val box = Box(Vec3.zero, Vec3(2, 2, 2))
    assert(intercept[MapmError](KernelRadiusChooser.choose(photons, box, queries, 5)).getMessage.contains("photon count"))
    assert(intercept[MapmError](KernelRadiusChooser.choose(Array.empty, box, queries, 1)).getMessage.contains("no photons"))
    assert(intercept[MapmError](KernelRadiusChooser.choose(photons, box, Array.empty, 1)).getMessage.contains("no query points"))
  }
}
