package mapm.model

import mapm.numerics._

import scala.collection.mutable

/** The polygon map (3.1.4 step 1): a KD-tree over the scene's triangles for ray casting, built with
  * the surface area heuristic.
  *
  * Build: at each node the SAH cost `traversal + intersect * (A_L N_L + A_R N_R) / A` is evaluated
  * at `bins - 1` evenly spaced planes on each axis (triangle bounding boxes counted in bins); the
  * cheapest plane splits the node unless a leaf (`intersect * N`) is cheaper, the node holds at most
  * `leafSize` triangles, or the depth reaches `maxDepth`. A plane that leaves one side empty gets a
  * 20% bonus (cutting off empty space pays). A triangle goes to the left child when its box
  * reaches the plane from below (min <= split) and to the right when it reaches it from above
  * (max >= split), so a triangle touching the plane is in both: every point of a triangle lies in
  * some leaf that lists it, which is what makes the traversal exact.
  *
  * Degenerate (zero-area) triangles are left out: they are never hit.
  *
  * Queries go through a [[TriKdTree.Query]] (one per thread) that owns its traversal stack, so casting
  * a ray allocates nothing. Ray/triangle tests use Moeller-Trumbore in double precision with
  * inclusive edges. Direction components that are exactly zero (axis-parallel rays) are handled
  * without forming 0 * Inf: such a ray never crosses a plane of that axis.
  */
final class TriKdTree private (
    val scene: Scene,
    tri: Array[Double],       // per triangle: v0 (3), e1 = v1-v0 (3), e2 = v2-v0 (3)
    usable: Array[Boolean],   // false for degenerate triangles
    nodeKind: Array[Int],     // 0, 1, 2: split axis; 3: leaf
    nodeSplit: Array[Double], // split position (inner nodes)
    nodeA: Array[Int],        // inner: index of the right child (the left child is node + 1); leaf: first slot in leafTris
    nodeB: Array[Int],        // leaf: number of triangles
    leafTris: Array[Int],
    rootLo: Array[Double],
    rootHi: Array[Double],
    val depth: Int) {

  /** Unit geometric (front-side) normal of each triangle; zero for degenerate ones. */
  val normals: Array[Vec3] = scene.triangles.map(_.normal).toArray

  def nodeCount: Int = nodeKind.length
  def leafCount: Int = nodeKind.count(_ == 3)
  /** Triangle references stored in leaves (a triangle that straddles planes counts once per leaf). */
  def leafReferences: Int = leafTris.length

  /** A query context for one thread. */
  def query(): TriKdTree.Query = new TriKdTree.Query(this)

  /** Ray parameter t > 0 where o + t d hits triangle `id`, or +Inf if it misses (always for a
    * degenerate triangle). The same test the tree uses, for brute-force checks. */
  def hitDistance(id: Int, o: Vec3, d: Vec3): Double =
    if (!usable(id)) Double.PositiveInfinity else intersect(id, o.x, o.y, o.z, d.x, d.y, d.z)

  /** Moeller-Trumbore: t of the hit, or +Inf (also for a ray parallel to the plane). */
  private def intersect(id: Int, ox: Double, oy: Double, oz: Double, dx: Double, dy: Double, dz: Double): Double = {
    val b = 9 * id
    val e1x = tri(b + 3); val e1y = tri(b + 4); val e1z = tri(b + 5)
    val e2x = tri(b + 6); val e2y = tri(b + 7); val e2z = tri(b + 8)
    val px = dy * e2z - dz * e2y
    val py = dz * e2x - dx * e2z
    val pz = dx * e2y - dy * e2x
    val det = e1x * px + e1y * py + e1z * pz
    if (det == 0 || det.isNaN) return Double.PositiveInfinity
    val inv = 1.0 / det
    val sx = ox - tri(b); val sy = oy - tri(b + 1); val sz = oz - tri(b + 2)
    val u = (sx * px + sy * py + sz * pz) * inv
    if (!(u >= 0 && u <= 1)) return Double.PositiveInfinity
    val qx = sy * e1z - sz * e1y
    val qy = sz * e1x - sx * e1z
    val qz = sx * e1y - sy * e1x
    val v = (dx * qx + dy * qy + dz * qz) * inv
    if (!(v >= 0 && u + v <= 1)) return Double.PositiveInfinity
    val t = (e2x * qx + e2y * qy + e2z * qz) * inv
    if (t > 0) t else Double.PositiveInfinity
  }

  /** Shared traversal: nearest hit in (tMin, tMax), or (anyHit) the first hit found. Returns the
    * triangle index (-1 for none) and leaves the distance in q.t. */
  private def traverse(q: TriKdTree.Query, ox: Double, oy: Double, oz: Double, dx: Double, dy: Double, dz: Double,
                       tMin: Double, tMax: Double, anyHit: Boolean): Int = {
    // Clip to the root box, one slab per axis; an axis the ray does not move along only tests containment.
    var t0 = tMin
    var t1 = tMax
    var a = 0
    while (a < 3) {
      val o = if (a == 0) ox else if (a == 1) oy else oz
      val d = if (a == 0) dx else if (a == 1) dy else dz
      if (d == 0) { if (o < rootLo(a) || o > rootHi(a)) return -1 }
      else {
        val ta = (rootLo(a) - o) / d
        val tb = (rootHi(a) - o) / d
        t0 = math.max(t0, math.min(ta, tb))
        t1 = math.min(t1, math.max(ta, tb))
      }
      a += 1
    }
    if (!(t0 <= t1)) return -1

    val stackNode = q.stackNode
    val stackT0 = q.stackT0
    val stackT1 = q.stackT1
    var sp = 0
    var best = tMax
    var bestTri = -1
    var node = 0
    while (true) {
      val kind = nodeKind(node)
      if (kind != 3) {
        val s = nodeSplit(node)
        val o = if (kind == 0) ox else if (kind == 1) oy else oz
        val d = if (kind == 0) dx else if (kind == 1) dy else dz
        val left = node + 1
        val right = nodeA(node)
        if (d == 0) node = if (o <= s) left else right
        else {
          val tS = (s - o) / d
          val belowFirst = o < s || (o == s && d < 0)
          val near = if (belowFirst) left else right
          val far = if (belowFirst) right else left
          if (tS > t1 || tS <= 0) node = near
          else if (tS < t0) node = far
          else {
            stackNode(sp) = far; stackT0(sp) = tS; stackT1(sp) = t1; sp += 1
            node = near
            t1 = tS
          }
        }
      } else {
        var k = nodeA(node)
        val end = k + nodeB(node)
        while (k < end) {
          val id = leafTris(k)
          val t = intersect(id, ox, oy, oz, dx, dy, dz)
          if (t > tMin && t < best) {
            best = t; bestTri = id
            if (anyHit) { q.t = t; return id }
          }
          k += 1
        }
        // Every leaf still on the stack lies beyond t1: a hit before it cannot be beaten.
        if (bestTri >= 0 && best <= t1) { q.t = best; return bestTri }
        if (sp == 0) { q.t = best; return bestTri }
        sp -= 1
        node = stackNode(sp); t0 = stackT0(sp); t1 = stackT1(sp)
      }
    }
    -1 // not reached
  }
}

object TriKdTree {
  /** SAH costs: one traversal step against one ray/triangle test. */
  private val TraversalCost = 1.0
  private val IntersectCost = 1.5
  private val EmptyBonus = 0.8

  /** Builds the tree. `maxDepth` defaults to 6 + log2(triangles): on Sponza (66k triangles) deeper
    * trees (the common 8 + 1.3 log2 n = 29) visit hardly fewer nodes and triangles per ray but have
    * four times the nodes and build time; on the Cornell box the limit is not reached. */
  def build(scene: Scene, leafSize: Int = 2, maxDepth: Int = -1, bins: Int = 32): TriKdTree = {
    require(leafSize >= 1 && bins >= 2)
    val n = scene.triangles.size
    val tri = new Array[Double](9 * n)
    val lo = new Array[Double](3 * n)
    val hi = new Array[Double](3 * n)
    val usable = new Array[Boolean](n)
    for ((t, i) <- scene.triangles.zipWithIndex) {
      val e1 = t.v1 - t.v0
      val e2 = t.v2 - t.v0
      Array(t.v0, e1, e2).zipWithIndex.foreach { case (v, j) =>
        tri(9 * i + 3 * j) = v.x; tri(9 * i + 3 * j + 1) = v.y; tri(9 * i + 3 * j + 2) = v.z
      }
      val b = t.bounds
      for (a <- 0 until 3) { lo(3 * i + a) = b.lo(a); hi(3 * i + a) = b.hi(a) }
      usable(i) = !t.degenerate
    }
    val ids = (0 until n).filter(usable).toArray
    val depthLimit = if (maxDepth >= 0) maxDepth else (6 + math.log(math.max(1, ids.length).toDouble) / math.log(2)).round.toInt
    val rootLo = Array.fill(3)(Double.MaxValue)
    val rootHi = Array.fill(3)(-Double.MaxValue)
    for (i <- ids; a <- 0 until 3) {
      rootLo(a) = math.min(rootLo(a), lo(3 * i + a)); rootHi(a) = math.max(rootHi(a), hi(3 * i + a))
    }
    if (ids.isEmpty) for (a <- 0 until 3) { rootLo(a) = 0; rootHi(a) = 0 }
    // Pad the root box a little so that rounding in the slab test cannot drop a hit on its faces.
    for (a <- 0 until 3) {
      val pad = 1e-9 * (rootHi(a) - rootLo(a) + math.abs(rootLo(a)) + math.abs(rootHi(a))) + 1e-300
      rootLo(a) -= pad; rootHi(a) += pad
    }

    val b = new Builder(lo, hi, leafSize, depthLimit, bins)
    b.node(ids, rootLo.clone(), rootHi.clone(), 0)
    new TriKdTree(scene, tri, usable, b.kind.toArray, b.split.toArray, b.na.toArray, b.nb.toArray, b.leafTris.toArray,
      rootLo, rootHi, b.deepest)
  }

  private final class Builder(lo: Array[Double], hi: Array[Double], leafSize: Int, maxDepth: Int, bins: Int) {
    val kind = mutable.ArrayBuffer.empty[Int]
    val split = mutable.ArrayBuffer.empty[Double]
    val na = mutable.ArrayBuffer.empty[Int]
    val nb = mutable.ArrayBuffer.empty[Int]
    val leafTris = mutable.ArrayBuffer.empty[Int]
    var deepest = 0
    private val minCount = new Array[Int](bins)
    private val maxCount = new Array[Int](bins)

    private def area(l: Array[Double], h: Array[Double]): Double = {
      val x = h(0) - l(0); val y = h(1) - l(1); val z = h(2) - l(2)
      2 * (x * y + y * z + z * x)
    }

    private def leaf(me: Int, ids: Array[Int]): Unit = {
      kind(me) = 3; na(me) = leafTris.size; nb(me) = ids.length
      leafTris ++= ids
    }

    def node(ids: Array[Int], nlo: Array[Double], nhi: Array[Double], depth: Int): Unit = {
      val me = kind.size
      kind += 3; split += 0; na += 0; nb += 0
      deepest = math.max(deepest, depth)
      val n = ids.length
      if (n <= leafSize || depth >= maxDepth) { leaf(me, ids); return }
      val sa = area(nlo, nhi)
      var bestCost = IntersectCost * n
      var bestAxis = -1
      var bestSplit = 0.0
      for (a <- 0 until 3) {
        val ext = nhi(a) - nlo(a)
        if (ext > 0 && sa > 0) {
          java.util.Arrays.fill(minCount, 0)
          java.util.Arrays.fill(maxCount, 0)
          def bin(x: Double): Int = math.min(bins - 1, math.max(0, ((x - nlo(a)) / ext * bins).toInt))
          for (id <- ids) { minCount(bin(lo(3 * id + a))) += 1; maxCount(bin(hi(3 * id + a))) += 1 }
          val b1 = (a + 1) % 3
          val b2 = (a + 2) % 3
          val e1 = nhi(b1) - nlo(b1)
          val e2 = nhi(b2) - nlo(b2)
          var nLeft = 0
          var nRight = n
          for (k <- 1 until bins) {
            nLeft += minCount(k - 1)   // boxes starting below plane k
            nRight -= maxCount(k - 1)  // boxes ending below plane k are gone from the right
            val s = nlo(a) + ext * k / bins
            val wl = s - nlo(a)
            val wr = nhi(a) - s
            val saL = 2 * (wl * e1 + e1 * e2 + e2 * wl)
            val saR = 2 * (wr * e1 + e1 * e2 + e2 * wr)
            var cost = TraversalCost + IntersectCost * (saL * nLeft + saR * nRight) / sa
            if (nLeft == 0 || nRight == 0) cost *= EmptyBonus
            if (cost < bestCost) { bestCost = cost; bestAxis = a; bestSplit = s }
          }
        }
      }
      if (bestAxis < 0) { leaf(me, ids); return }
      val left = ids.filter(id => lo(3 * id + bestAxis) <= bestSplit)
      val right = ids.filter(id => hi(3 * id + bestAxis) >= bestSplit)
      if (left.length == n && right.length == n) { leaf(me, ids); return }
      kind(me) = bestAxis; split(me) = bestSplit
      val lhi = nhi.clone(); lhi(bestAxis) = bestSplit
      val rlo = nlo.clone(); rlo(bestAxis) = bestSplit
      node(left, nlo, lhi, depth + 1)
      na(me) = kind.size
      node(right, rlo, nhi, depth + 1)
    }
  }

  /** Per-thread query state: the traversal stack and the last hit. */
  final class Query private[TriKdTree] (tree: TriKdTree) {
    private[TriKdTree] val stackNode = new Array[Int](tree.depth + 2)
    private[TriKdTree] val stackT0 = new Array[Double](tree.depth + 2)
    private[TriKdTree] val stackT1 = new Array[Double](tree.depth + 2)
    /** Ray parameter of the last hit. */
    var t: Double = Double.PositiveInfinity
    /** Triangle of the last hit, -1 after a miss. */
    var triangle: Int = -1

    /** Nearest hit of o + t d with t in (tMin, tMax); sets [[t]] and [[triangle]]. */
    def nearest(ox: Double, oy: Double, oz: Double, dx: Double, dy: Double, dz: Double,
                tMin: Double, tMax: Double): Boolean = {
      triangle = tree.traverse(this, ox, oy, oz, dx, dy, dz, tMin, tMax, anyHit = false)
      triangle >= 0
    }

    def nearest(o: Vec3, d: Vec3, tMin: Double = 0.0, tMax: Double = Double.PositiveInfinity): Boolean =
      nearest(o.x, o.y, o.z, d.x, d.y, d.z, tMin, tMax)

    /** Whether anything is hit with t in (tMin, tMax) (a shadow ray); [[triangle]] is one such hit. */
    def occluded(o: Vec3, d: Vec3, tMin: Double, tMax: Double): Boolean = {
      triangle = tree.traverse(this, o.x, o.y, o.z, d.x, d.y, d.z, tMin, tMax, anyHit = true)
      triangle >= 0
    }
  }
}
