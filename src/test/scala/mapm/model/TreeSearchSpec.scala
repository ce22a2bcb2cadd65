package mapm.model

import mapm.numerics._

import mapm.Slow
import org.scalatest.funsuite.AnyFunSuite

@Slow
class TreeSearchSpec extends AnyFunSuite {
  private def bd(d: Double) = new java.math.BigDecimal(d)

  private def photonsOf(pts: Array[Vec3]): Array[Photon] = pts.map(p => Photon(p, Vec3(1, 1, 1), Vec3(0, -1, 0), Vec3(0, 1, 0)))

  private def searchOf(map: PhotonMap, q: Vec3, h: Double): (Seq[Int], Seq[Int]) = {
    val s = new TreeSearcher(map.search)
    val f = map.format
    s.search(f.quantize(q.x), f.quantize(q.y), f.quantize(q.z), f.quantize(h))
    (s.visited.take(s.tsCount).toSeq, s.so.take(s.soCount).toSeq)
  }

  // The three example searches of dissertation 3.1.6 on the Table 3.1 tree, h = 100. Visited nodes
  // are the TS operations; the leaves the prose "examines" arrive as SOs. Example (c): the pseudo
  // code also issues an SO for node 1 (TC_L and TC_R both hold there), which the prose omits.
  private val examples = Seq(
    ("a", Vec3(0, 358.739, 280.736), Seq(0, 4), Seq(5, 6, 4)),
    ("b", Vec3(0, 473.547, 255.165), Seq(0, 1, 4), Seq(0, 2, 5, 6, 4)),
    ("c", Vec3(213.296, 0, 26.6906), Seq(0, 1), Seq(2, 3, 1)))

  for (fmt <- Seq(FloatFormat.fp64, FloatFormat.fp32, FloatFormat.fp16))
    test(s"the three example searches of 3.1.6 (h = 100) in $fmt") {
      val map = PhotonMap.build(photonsOf(Table31.photons), Table31.box, fmt, 100.0)
      for ((name, q, ts, so) <- examples) {
        val (v, s) = searchOf(map, q, 100.0)
        assert(v == ts, s"example ($name) visited nodes")
        assert(s == so, s"example ($name) shader operations")
      }
    }

  test("one-node tree: the root is searched as a node; an empty tree yields nothing") {
    val box = Box(Vec3(0, 0, 0), Vec3(10, 10, 10))
    val map = PhotonMap.build(photonsOf(Array(Vec3(5, 5, 5))), box, FloatFormat.fp32, 1.0)
    assert(map.tree.axis(0) == 0) // all extents tie: x
    assert(searchOf(map, Vec3(5.5, 9, 9), 1.0) == ((Seq(0), Seq(0)))) // |5.5 - 5| < 1 on x: SO
    assert(searchOf(map, Vec3(6, 5, 5), 1.0) == ((Seq(0), Seq()))) // 6 - 1 < 5 fails (strict)
    assert(searchOf(map, Vec3(4, 5, 5), 1.0) == ((Seq(0), Seq()))) // 4 + 1 > 5 fails (strict)
    val empty = PhotonMap.build(Array.empty[Photon], box, FloatFormat.fp32, 1.0)
    assert(searchOf(empty, Vec3(5, 5, 5), 1.0) == ((Seq(), Seq())))
  }

  test("TC_L and TC_R are exact on format values, also where the double sum rounds onto s") {
    val rnd = new scala.util.Random(5)
    val f = FloatFormat.fp32
    def rndVal(): Double = {
      val v = f.quantize(math.pow(2, rnd.nextInt(80) - 40) * (1 + rnd.nextDouble()))
      if (rnd.nextInt(10) == 0) 0.0 else if (rnd.nextBoolean()) v else -v
    }
    var ambiguous = 0
    for (_ <- 0 until 200000) {
      val p = rndVal(); val h = math.abs(rndVal()) max f.minNormal
      // candidates for s: near p, near p -/+ h as rounded in double and in the format
      val cands = Seq(p, p - h, p + h, f.quantize(p - h), f.quantize(p + h), Math.nextUp(f.quantize(p - h).toFloat).toDouble,
        Math.nextDown(f.quantize(p + h).toFloat).toDouble, rndVal())
      for (s <- cands if f.tryEncode(s).exists(b => f.decode(b) == s)) {
        val wantL = bd(p).subtract(bd(h)).compareTo(bd(s)) < 0
        val wantR = bd(p).add(bd(h)).compareTo(bd(s)) > 0
        if (p - h == s || p + h == s) ambiguous += 1
        assert(TreeCompare.tcL(p, h, s) == wantL, s"TC_L p=$p h=$h s=$s")
        assert(TreeCompare.tcR(p, h, s) == wantR, s"TC_R p=$p h=$h s=$s")
      }
    }
    assert(ambiguous > 1000) // the TwoSum branch was exercised
  }

  /** Independent reference of the pseudo code: recursion with exact BigDecimal comparisons on the
    * tree's own fields; returns (visited nodes, SO nodes) as multisets. */
  private def referenceSearch(map: PhotonMap, q: Array[Double], h: Double): (Seq[Int], Seq[Int]) = {
    val t = map.tree
    val f = map.format
    val visited = Seq.newBuilder[Int]; val so = Seq.newBuilder[Int]
    def rec(i: Int): Unit = {
      visited += i
      val p = bd(q(t.axis(i))); val s = bd(f.decode(map.split(i)))
      val tcl = p.subtract(bd(h)).compareTo(s) < 0
      val tcr = p.add(bd(h)).compareTo(s) > 0
      if (tcl && t.hasLeft(i)) { if (t.isLeaf(t.left(i))) so += t.left(i) else rec(t.left(i)) }
      if (tcr && t.hasRight(i)) { if (t.isLeaf(t.right(i))) so += t.right(i) else rec(t.right(i)) }
      if (tcl && tcr) so += i
    }
    if (t.size > 0) rec(0)
    (visited.result().sorted, so.result().sorted)
  }

  for ((fmt, seed) <- Seq((FloatFormat.fp32, 1), (FloatFormat(5, 4), 2), (FloatFormat.bf16, 3)))
    test(s"random data in $fmt: search equals the reference, and finds every photon within h") {
      val rnd = new scala.util.Random(seed)
      val f = fmt
      for (trial <- 0 until 12) {
        val n = rnd.nextInt(2500) + 1
        val scale = if (f.expWidth <= 5) 40.0 else 1000.0
        // clustered points on a few planes (like photons on walls) plus uniform ones
        val pts = Array.fill(n) {
          val v = Vec3(rnd.nextDouble() * scale, rnd.nextDouble() * scale, rnd.nextDouble() * scale)
          rnd.nextInt(4) match {
            case 0 => v.copy(y = 0); case 1 => v.copy(x = scale); case _ => v
          }
        }
        val map = PhotonMap.build(photonsOf(pts), Box(Vec3(0, 0, 0), Vec3(scale, scale, scale)), f, scale * (0.02 + 0.1 * rnd.nextDouble()))
        val h = map.hValue
        val searcher = new TreeSearcher(map.search)
        for (_ <- 0 until 100) {
          val q = Array.fill(3)(f.quantize(rnd.nextDouble() * scale * 1.1 - scale * 0.05))
          searcher.search(q(0), q(1), q(2), h)
          val visited = searcher.visited.take(searcher.tsCount).toSeq
          val so = searcher.so.take(searcher.soCount).toSeq
          val (rv, rso) = referenceSearch(map, q, h)
          assert(visited.sorted == rv && so.sorted == rso)
          assert(so.distinct.length == so.length, "an SO issued twice")
          assert(visited.forall(i => !map.tree.isLeaf(i) || i == 0), "a leaf reached by a TS")
          // every photon strictly within h (exact arithmetic on the quantized values) got an SO
          val soSet = so.toSet
          for (i <- 0 until map.size) {
            val d2 = Seq(map.px(i), map.py(i), map.pz(i)).zip(q).map { case (b, c) => val d = bd(f.decode(b)).subtract(bd(c)); d.multiply(d) }
              .reduce(_ add _)
            if (d2.compareTo(bd(h).multiply(bd(h))) < 0) assert(soSet(i), s"photon at node $i within h missed")
          }
          // a node's own photon is issued only with both comparisons true: it lies in the slab
          for (i <- so if !map.tree.isLeaf(i) || map.size == 1) {
            val p = bd(q(map.tree.axis(i))); val s = bd(map.search.split(i))
            assert(p.subtract(bd(h)).compareTo(s) < 0 && p.add(bd(h)).compareTo(s) > 0)
          }
        }
      }
    }
}
