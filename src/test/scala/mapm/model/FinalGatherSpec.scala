package mapm.model

import mapm.numerics._

import org.scalatest.funsuite.AnyFunSuite

class FinalGatherSpec extends AnyFunSuite {
  private val cfg = SceneConfig.load(TestScenes.cornellScene)
  private val tree = TriKdTree.build(cfg.scene)
  private val primary = PrimaryHits.trace(tree, cfg.camera, cfg.width, cfg.height)

  test("Cornell query points: valid pixels and contributions Kd(x) Kd(y) / N from the MTL's values") {
    val n = cfg.finalGatherRays
    val qs = FinalGather.queries(tree, primary, n, cfg.seed)
    val pixels = cfg.width * cfg.height
    assert(qs.length <= pixels * n && qs.length > pixels * n / 2)
    assert(qs.forall(q => q.pixel >= 0 && q.pixel < pixels))
    assert(qs.map(_.pixel).sliding(2).forall(w => w.length < 2 || w(0) <= w(1)), "pixel order")
    assert(qs.groupBy(_.pixel).values.forall(_.length <= n))
    // Reflectances written in cornell-box.mtl.
    val kds = Seq(Vec3(0.725, 0.71, 0.68), Vec3(0.63, 0.065, 0.05), Vec3(0.14, 0.45, 0.091))
    val allowed = for (a <- kds; b <- kds) yield a.mul(b) / n
    for (q <- qs) {
      val c = q.contribution
      assert(c.x >= 0 && c.x <= 1 && c.y >= 0 && c.y <= 1 && c.z >= 0 && c.z <= 1)
      assert(allowed.exists(a => (a - c).length < 1e-15), s"$c is no product of two reflectances / $n")
      assert(cfg.scene.bounds.contains(q.position))
      assert(math.abs(q.normal.length - 1) < 1e-12)
    }
  }

  test("query normals face back towards the pixel's primary hit; the gather rays leave on the camera's side") {
    val qs = FinalGather.queries(tree, primary, 8, 3)
    for (q <- qs) {
      val x = primary.position(q.pixel)
      val toX = x - q.position
      assert(q.normal.dot(toX) > 0)
      assert(primary.normal(q.pixel).dot(-toX) > 0)
    }
  }

  test("deterministic for a seed, independent of the thread count") {
    val a = FinalGather.queries(tree, primary, 6, 42, threads = 1)
    val b = FinalGather.queries(tree, primary, 6, 42, threads = 2)
    val c = FinalGather.queries(tree, primary, 6, 42, threads = 3)
    assert(a.sameElements(b) && a.sameElements(c))
    assert(!a.sameElements(FinalGather.queries(tree, primary, 6, 43, threads = 2)))
  }

  test("inside a closed box every gather ray hits: exactly pixels * N query points") {
    val box = TestScenes.closedBox(100, Vec3(0.5, 0.5, 0.5))
    val t = TriKdTree.build(box)
    val cam = Camera(Vec3(50, 50, 1), Vec3(0, 0, 1), Vec3(0, 1, 0), 60)
    val prim = PrimaryHits.trace(t, cam, 8, 6)
    val qs = FinalGather.queries(t, prim, 5, 1)
    assert(qs.length == 8 * 6 * 5)
    assert(qs.forall(_.contribution == Vec3(0.05, 0.05, 0.05)))
  }

  test("the compact query points hold the same points as the objects, in the same order") {
    val g = FinalGather.gather(tree, primary, 4, 9, threads = 2)
    val qs = FinalGather.queries(tree, primary, 4, 9, threads = 1)
    assert(g.length == qs.length && g.toArray.sameElements(qs))
    assert(QueryPoints.of(qs).toArray.sameElements(qs))
    assert((0 until g.length).forall(i => g.position(i) == qs(i).position && g.contribution(i) == qs(i).contribution))
  }
}
