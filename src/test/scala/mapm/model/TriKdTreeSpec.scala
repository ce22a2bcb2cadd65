package mapm.model

import mapm.numerics._

import mapm.Slow
import mapm.testutil.SharedFiles
import org.scalatest.funsuite.AnyFunSuite

@Slow
class TriKdTreeSpec extends AnyFunSuite with SharedFiles {

  /** Nearest hit over all triangles: (t, triangle), (+Inf, -1) on a miss. */
  private def bruteForce(tree: TriKdTree, o: Vec3, d: Vec3): (Double, Int) = {
    var best = Double.PositiveInfinity
    var id = -1
    for (i <- tree.scene.triangles.indices) {
      val t = tree.hitDistance(i, o, d)
      if (t < best) { best = t; id = i }
    }
    (best, id)
  }

  /** Checks the tree's nearest and any-hit answers against brute force for one ray. */
  private def check(tree: TriKdTree, q: TriKdTree.Query, o: Vec3, d: Vec3, what: => String): Unit = {
    val (bt, bid) = bruteForce(tree, o, d)
    val hit = q.nearest(o, d)
    assert(hit == (bid >= 0), s"hit/miss differs for $what: o=$o d=$d brute=$bt")
    if (hit) {
      assert(q.t == bt, s"t differs for $what: o=$o d=$d tree=${q.t} (tri ${q.triangle}) brute=$bt (tri $bid)")
      assert(q.triangle == bid || tree.hitDistance(q.triangle, o, d) == bt, s"triangle for $what")
      assert(!tree.scene.triangles(q.triangle).degenerate)
    }
    // Shadow rays: blocked before a distance iff the nearest hit is closer.
    for (limit <- Seq(bt * 0.5, bt * 1.5, 1e9) if !limit.isNaN && !limit.isInfinite)
      assert(q.occluded(o, d, 0, limit) == (bt < limit), s"occluded(<$limit) for $what")
  }

  /** Random triangles with coordinates on a coarse grid (so that many of them, the rays' origins
    * and the split planes share planes), plus degenerate ones: repeated and collinear vertices. */
  private def randomScene(rnd: scala.util.Random, n: Int, degenerate: Int): Scene = {
    def gridPoint(): Vec3 = Vec3(rnd.nextInt(21) * 5.0, rnd.nextInt(21) * 5.0, rnd.nextInt(21) * 5.0)
    def jitter(p: Vec3, s: Double) = p + Vec3(rnd.nextGaussian(), rnd.nextGaussian(), rnd.nextGaussian()) * s
    val normal = Vector.fill(n) {
      val a = gridPoint()
      if (rnd.nextBoolean()) {
        // axis-aligned triangle: one coordinate shared
        val axis = rnd.nextInt(3)
        def p() = { val q = jitter(a, 8); Vec3(if (axis == 0) a.x else q.x, if (axis == 1) a.y else q.y, if (axis == 2) a.z else q.z) }
        Triangle(a, p(), p(), 0)
      } else Triangle(a, jitter(a, 10), jitter(a, 10), 0)
    }
    val degen = Vector.fill(degenerate) {
      val a = gridPoint()
      val b = jitter(a, 10)
      rnd.nextInt(3) match {
        case 0 => Triangle(a, a, b, 0)
        case 1 => Triangle(a, b, a + (b - a) * 0.5, 0)
        case _ => Triangle(a, a, a, 0)
      }
    }
    Scene(rnd.shuffle(normal ++ degen), Vector(Material("m", Vec3(0.5, 0.5, 0.5), Vec3.zero)))
  }

  private def randomRay(rnd: scala.util.Random): (Vec3, Vec3, String) = {
    val o =
      if (rnd.nextInt(3) == 0) Vec3(rnd.nextInt(25) * 5.0 - 10, rnd.nextInt(25) * 5.0 - 10, rnd.nextInt(25) * 5.0 - 10)
      else Vec3(rnd.nextDouble() * 140 - 20, rnd.nextDouble() * 140 - 20, rnd.nextDouble() * 140 - 20)
    rnd.nextInt(4) match {
      case 0 => // along one axis
        val a = rnd.nextInt(3); val s = if (rnd.nextBoolean()) 1.0 else -1.0
        (o, Vec3(if (a == 0) s else 0, if (a == 1) s else 0, if (a == 2) s else 0), "axis ray")
      case 1 => // in an axis plane (one component exactly zero)
        val a = rnd.nextInt(3)
        val v = Vec3(rnd.nextGaussian(), rnd.nextGaussian(), rnd.nextGaussian())
        (o, Vec3(if (a == 0) 0 else v.x, if (a == 1) 0 else v.y, if (a == 2) 0 else v.z).normalized, "planar ray")
      case _ =>
        (o, Vec3(rnd.nextGaussian(), rnd.nextGaussian(), rnd.nextGaussian()).normalized, "random ray")
    }
  }

  test("nearest and any-hit equal brute force on random scenes with degenerate triangles and axis-parallel rays") {
    val rnd = new scala.util.Random(20140601)
    var rays = 0
    var hits = 0
    for (sceneNo <- 0 until 6) {
      val scene = randomScene(rnd, n = Seq(1, 7, 60, 300, 1000, 2000)(sceneNo), degenerate = 10 * sceneNo + 1)
      for (leafSize <- Seq(1, 4)) {
        val tree = TriKdTree.build(scene, leafSize = leafSize)
        val q = tree.query()
        for (_ <- 0 until 700) {
          val (o, d, what) = randomRay(rnd)
          check(tree, q, o, d, s"$what, scene $sceneNo")
          rays += 1
          if (q.nearest(o, d)) hits += 1
        }
      }
    }
    assert(rays == 8400 && hits > rays / 10, s"$hits hits of $rays rays: the test should hit often")
  }

  test("degenerate triangles alone: never hit, never a crash") {
    val p = Vec3(1, 1, 1)
    val scene = Scene(Vector(Triangle(p, p, p, 0), Triangle(Vec3(0, 0, 0), Vec3(1, 1, 1), Vec3(2, 2, 2), 0),
      Triangle(Vec3(0, 0, 0), Vec3(0, 0, 0), Vec3(0, 5, 0), 0)), Vector(Material("m", Vec3.one, Vec3.zero)))
    val tree = TriKdTree.build(scene)
    val q = tree.query()
    val rnd = new scala.util.Random(3)
    for (_ <- 0 until 500) {
      val (o, d, _) = randomRay(rnd)
      assert(!q.nearest(o, d) && !q.occluded(o, d, 0, Double.PositiveInfinity))
    }
    // Straight through the degenerate ones' points and along their lines.
    assert(!q.nearest(Vec3(1, 1, -5), Vec3(0, 0, 1)))
    assert(!q.nearest(Vec3(-1, -1, -1), Vec3(1, 1, 1).normalized))
    assert(!q.nearest(Vec3(0, -3, 0), Vec3(0, 1, 0)))
  }

  test("Moeller-Trumbore agrees with exact rational intersection on integer triangles and rays") {
    // Solve o + t d = v0 + u e1 + v e2 exactly by Cramer's rule over the integers.
    def det(a: Array[BigInt], b: Array[BigInt], c: Array[BigInt]): BigInt =
      a(0) * (b(1) * c(2) - b(2) * c(1)) - a(1) * (b(0) * c(2) - b(2) * c(0)) + a(2) * (b(0) * c(1) - b(1) * c(0))
    val rnd = new scala.util.Random(99)
    var checked = 0
    var hits = 0
    while (checked < 20000) {
      def iv(r: Int) = Array.fill(3)(BigInt(rnd.nextInt(2 * r + 1) - r))
      val v0 = iv(20); val v1 = iv(20); val v2 = iv(20); val o = iv(40)
      val d = rnd.nextInt(4) match {
        case 0 => val a = iv(3); a(rnd.nextInt(3)) = 0; a // one component exactly zero
        case 1 => iv(5)
        case _ => val n = iv(2); Array.tabulate(3)(i => v0(i) + v1(i) + v2(i) - 3 * o(i) + n(i)) // towards the centroid
      }
      if (d.exists(_ != 0)) {
        val e1 = Array.tabulate(3)(i => v1(i) - v0(i))
        val e2 = Array.tabulate(3)(i => v2(i) - v0(i))
        val s = Array.tabulate(3)(i => o(i) - v0(i))
        val nd = d.map(-_)
        val den = det(e1, e2, nd)
        // u = det(s, e2, -d)/den, v = det(e1, s, -d)/den, t = det(e1, e2, s)/den
        val (un, vn, tn) = (det(s, e2, nd), det(e1, s, nd), det(e1, e2, s))
        val sgn = den.signum
        val exactHit = sgn != 0 && un * sgn >= 0 && vn * sgn >= 0 && (un + vn - den) * sgn <= 0 && tn * sgn > 0
        // Skip rays that graze an edge or start on the plane: there rounding may decide either way.
        val margin = den.abs.toDouble * 1e-9
        val onEdge = sgn != 0 && (un.abs.toDouble <= margin || vn.abs.toDouble <= margin ||
          (un + vn - den).abs.toDouble <= margin || tn.abs.toDouble <= margin)
        if (!onEdge) {
          def vec(a: Array[BigInt]) = Vec3(a(0).toDouble, a(1).toDouble, a(2).toDouble)
          val tri = Triangle(vec(v0), vec(v1), vec(v2), 0)
          val tree = TriKdTree.build(Scene(Vector(tri), Vector(Material("m", Vec3.one, Vec3.zero))))
          val t = tree.hitDistance(0, vec(o), vec(d))
          if (sgn == 0) assert(t.isInfinite, s"parallel or degenerate: $tri o=${vec(o)} d=${vec(d)}")
          else {
            assert(!t.isInfinite == exactHit, s"$tri o=${vec(o)} d=${vec(d)} exact=$exactHit t=$t")
            if (exactHit) {
              val exactT = BigDecimal(tn) / BigDecimal(den)
              assert(math.abs(t - exactT.toDouble) <= 1e-9 * math.max(1, exactT.toDouble.abs))
              hits += 1
            }
          }
          checked += 1
        }
      }
    }
    assert(hits > 5000, s"only $hits hits")
  }

  test("Cornell box: rays from the camera and from random inside points equal brute force") {
    val scene = ObjLoader.load(TestScenes.cornellObj, Vec3.one)
    val tree = TriKdTree.build(scene)
    val q = tree.query()
    val rnd = new scala.util.Random(5)
    for (_ <- 0 until 3000) {
      val o = if (rnd.nextBoolean()) Vec3(278, 273, -530) else Vec3(rnd.nextDouble() * 556, rnd.nextDouble() * 548.8, rnd.nextDouble() * 559.2)
      val d = if (rnd.nextInt(3) == 0) randomRay(rnd)._2 else Vec3(rnd.nextGaussian(), rnd.nextGaussian(), rnd.nextGaussian() + 1).normalized
      check(tree, q, o, d, "Cornell ray")
    }
    // Inside the closed part of the box every upward ray hits something: the ceiling at the latest.
    for (_ <- 0 until 200) {
      val o = Vec3(1 + rnd.nextDouble() * 540, 331 + rnd.nextDouble() * 200, 1 + rnd.nextDouble() * 550)
      assert(q.nearest(o, Vec3(0, 1, 0)) && math.abs(o.y + q.t - 548.8) < 1e-9)
    }
  }

  test("Sponza (66,454 triangles): random rays equal brute force") {
    val path = requireShared("scenes/sponza/sponza.obj")
    val scene = ObjLoader.load(path, Vec3(0.75, 0.75, 0.75))
    assert(scene.triangles.size == 66454)
    val tree = TriKdTree.build(scene)
    val q = tree.query()
    val rnd = new scala.util.Random(11)
    val b = scene.bounds
    var hits = 0
    for (_ <- 0 until 150) {
      val o = b.lo + b.extent.mul(Vec3(rnd.nextDouble(), rnd.nextDouble() * 0.8, rnd.nextDouble()))
      val (_, d, what) = randomRay(rnd)
      check(tree, q, o, d, s"Sponza $what")
      if (q.nearest(o, d)) hits += 1
    }
    assert(hits > 100)
  }
}
