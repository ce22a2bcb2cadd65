package mapm.model

import mapm.numerics._

import mapm.MapmError
import org.scalatest.funsuite.AnyFunSuite

class PhotonTracerSpec extends AnyFunSuite {
  import TestScenes._

  private lazy val cornell = SceneConfig.load(cornellScene)
  private lazy val cornellTree = TriKdTree.build(cornell.scene)
  private lazy val area = SceneConfig.load(cornellAreaScene)
  private lazy val areaTree = TriKdTree.build(area.scene)

  private def cornellPhotons(seed: Long, threads: Int) =
    PhotonTracer.trace(cornellTree, cornell.pointLights, cornell.photons, cornell.maxBounces, seed, threads)

  test("same seed gives identical photons for 1, 2 and 3 threads; another seed gives others") {
    val a = cornellPhotons(1, 1)
    assert(a.photons.length == 2000)
    for (threads <- Seq(2, 3)) {
      val b = cornellPhotons(1, threads)
      assert(b.photons.sameElements(a.photons) && b.emittedPaths == a.emittedPaths, s"$threads threads differ")
    }
    assert(!cornellPhotons(2, 2).photons.sameElements(a.photons), "seed 2 equals seed 1")
    val ar1 = PhotonTracer.trace(areaTree, Nil, 3000, 5, 9, 1)
    val ar2 = PhotonTracer.trace(areaTree, Nil, 3000, 5, 9, 2)
    assert(ar1.photons.sameElements(ar2.photons) && ar1.emittedPaths == ar2.emittedPaths, "area light: threads differ")
  }

  /** Distance from p to triangle t, computed independently: the nearest of the plane projection
    * (if inside, by edge sign tests) and the three edges. */
  private def distance(p: Vec3, t: Triangle): Double = {
    def segment(a: Vec3, b: Vec3): Double = {
      val ab = b - a
      val s = math.max(0.0, math.min(1.0, (p - a).dot(ab) / ab.dot(ab)))
      (a + ab * s - p).length
    }
    val n = t.normal
    val proj = p - n * (p - t.v0).dot(n)
    def side(a: Vec3, b: Vec3) = (b - a).cross(proj - a).dot(n)
    val inside = side(t.v0, t.v1) >= 0 && side(t.v1, t.v2) >= 0 && side(t.v2, t.v0) >= 0
    val edges = math.min(segment(t.v0, t.v1), math.min(segment(t.v1, t.v2), segment(t.v2, t.v0)))
    if (inside) math.min(math.abs((p - t.v0).dot(n)), edges) else edges
  }

  private def checkOnGeometry(scene: Scene, photons: Array[Photon]): Unit = {
    val tris = scene.triangles.filter(!_.degenerate)
    for (ph <- photons) {
      assert(scene.bounds.contains(ph.position), s"${ph.position} outside ${scene.bounds}")
      assert(ph.position.x >= 0 && ph.position.y >= 0 && ph.position.z >= 0)
      assert(tris.map(distance(ph.position, _)).min < 1e-9 * scene.scale, s"${ph.position} is on no triangle")
      assert(math.abs(ph.incoming.length - 1) < 1e-12 && math.abs(ph.normal.length - 1) < 1e-12)
      assert(ph.normal.dot(ph.incoming) < 0, "normal faces the incoming photon")
      assert(ph.power.x >= 0 && ph.power.y >= 0 && ph.power.z >= 0 && ph.power.maxComponent > 0)
    }
  }

  test("Cornell box photons lie on triangles inside the scene box, facing their direction") {
    checkOnGeometry(cornell.scene, cornellPhotons(1, 2).photons)
    checkOnGeometry(area.scene, PhotonTracer.trace(areaTree, Nil, 2000, 5, 1).photons)
  }

  test("closed box, one bounce: every path stores one photon and together they carry the light's power") {
    val box = closedBox(100, Vec3(0.5, 0.5, 0.5))
    val tree = TriKdTree.build(box)
    val power = Vec3(300, 200, 100)
    val r = PhotonTracer.trace(tree, Seq(PointLight(Vec3(30, 40, 50), power)), 5000, 1, 3)
    assert(r.emittedPaths == 5000 && r.photons.length == 5000)
    val total = r.photons.map(_.power).reduce(_ + _)
    for (c <- 0 until 3) assert(math.abs(total(c) - power(c)) < 1e-9 * power(c))
    // first hits from a point light: the incoming direction points from the light to the photon
    for (p <- r.photons) assert(((p.position - Vec3(30, 40, 50)).normalized - p.incoming).length < 1e-9)
    checkOnGeometry(box, r.photons)
  }

  test("closed box, five bounces: stored power is P (1 + kd + kd^2 + kd^3 + kd^4) (Russian roulette is unbiased)") {
    val kd = Vec3(0.5, 0.25, 0.8)
    val tree = TriKdTree.build(closedBox(100, kd))
    val power = Vec3(1000, 1000, 1000)
    val r = PhotonTracer.trace(tree, Seq(PointLight(Vec3(50, 50, 50), power)), 40000, 5, 7)
    val total = r.photons.map(_.power).reduce(_ + _)
    for (c <- 0 until 3) {
      val k = kd(c)
      val want = power(c) * (1 + k + k * k + k * k * k + k * k * k * k)
      assert(math.abs(total(c) / want - 1) < 0.03, s"channel $c: ${total(c)} vs $want")
    }
    // survival is max(kd) = 0.8: about 1 + .8 + .64 + .512 + .4096 = 3.36 photons per path
    assert(math.abs(40000.0 / r.emittedPaths - 3.3616) < 0.1)
  }

  test("area light in a closed box: first hits carry pi * area * Ke, leaving the lamp downwards") {
    val ke = Vec3(2, 3, 4)
    val box = closedBox(10, Vec3(0.5, 0.5, 0.5), Some(ke))
    val tree = TriKdTree.build(box)
    val r = PhotonTracer.trace(tree, Nil, 4000, 1, 5)
    assert(r.emittedPaths == 4000)
    val total = r.photons.map(_.power).reduce(_ + _)
    val want = ke * (math.Pi * 100)
    for (c <- 0 until 3) assert(math.abs(total(c) / want(c) - 1) < 1e-9)
    assert(r.photons.forall(_.incoming.y < 0))
    // Cosine emission: the photons on the floor (y = 0) are a fraction of all; on the four walls the rest.
    val floor = r.photons.count(_.position.y == 0).toDouble / 4000
    // Form factor between facing unit squares at distance 1 (a standard result): 0.1998.
    assert(math.abs(floor - 0.1998) < 0.025, s"floor fraction $floor")
  }

  test("point lights and area lights share photons by power") {
    val box = closedBox(10, Vec3(0.5, 0.5, 0.5), Some(Vec3(1, 1, 1)))
    val tree = TriKdTree.build(box)
    // lamp power pi * 100 * (1+1+1); the point light gets three times as much
    val pointPower = math.Pi * 100 * 3
    val r = PhotonTracer.trace(tree, Seq(PointLight(Vec3(5, 1, 5), Vec3(pointPower, pointPower, pointPower))), 8000, 1, 2)
    val fromPoint = r.photons.count(p => ((p.position - Vec3(5, 1, 5)).normalized - p.incoming).length < 1e-9)
    assert(math.abs(fromPoint / 8000.0 - 0.75) < 0.02, s"$fromPoint of 8000 from the point light")
  }

  test("no light, zero photons, and lights that miss everything") {
    val tree = TriKdTree.build(closedBox(10, Vec3(0.5, 0.5, 0.5)))
    assert(intercept[MapmError](PhotonTracer.trace(tree, Nil, 10, 5, 1)).getMessage.contains("no light"))
    assert(PhotonTracer.trace(tree, Seq(PointLight(Vec3(5, 5, 5), Vec3.one)), 0, 5, 1).photons.isEmpty)
    val single = TriKdTree.build(Scene(Vector(Triangle(Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0), 0)),
      Vector(Material("m", Vec3.one, Vec3.zero))))
    val e = intercept[MapmError](PhotonTracer.trace(single, Seq(PointLight(Vec3(1e6, 1e6, 1e6), Vec3.one)), 10, 5, 1))
    assert(e.getMessage.contains("hardly reach"))
  }
}
