package mapm.model

import mapm.numerics._

import mapm.MapmError
import org.scalatest.funsuite.AnyFunSuite

object Table31 {
  /** The seven photons of dissertation 3.1.4, in their initial slot order. */
  val photons: Array[Vec3] = Array(
    Vec3(312.808, 548.8, 8.8027),
    Vec3(264.63, 428.347, 559.2),
    Vec3(0, 44.8259, 495.07),
    Vec3(28.2439, 0, 7.08738),
    Vec3(72.7003, 548.8, 191.099),
    Vec3(0, 509.39, 171.588),
    Vec3(114.27, 84.3132, 117.435))
  /** The scene box of the example. */
  val box: Box = Box(Vec3(0, 0, 0.769442), Vec3(555.036, 548.8, 559.2))
  /** Table 3.1: index, left child, right child (-1 for none), photon coordinates. */
  val table: Seq[(Int, Int, Int, Vec3)] = Seq(
    (0, 1, 4, Vec3(0, 509.39, 171.588)),
    (1, 2, 3, Vec3(114.27, 84.3132, 117.435)),
    (2, -1, -1, Vec3(28.2439, 0, 7.08738)),
    (3, -1, -1, Vec3(312.808, 548.8, 8.8027)),
    (4, 5, 6, Vec3(72.7003, 548.8, 191.099)),
    (5, -1, -1, Vec3(0, 44.8259, 495.07)),
    (6, -1, -1, Vec3(264.63, 428.347, 559.2)))
  /** Split axes stated in the worked example: node 0 on z, nodes 1 and 4 on x. */
  val axes: Map[Int, Int] = Map(0 -> 2, 1 -> 0, 4 -> 0)
}

class PhotonTreeSpec extends AnyFunSuite {

  test("Table 3.1 is rebuilt node for node from the seven photons of 3.1.4") {
    val t = PhotonTree.build(Table31.photons, Table31.box)
    assert(t.size == 7)
    for ((i, l, r, pos) <- Table31.table) {
      assert(t.left(i) == l, s"node $i left")
      assert(t.right(i) == r, s"node $i right")
      assert(t.position(i) == pos, s"node $i photon")
    }
    for ((i, a) <- Table31.axes) assert(t.axis(i) == a, s"node $i axis")
    assert(t.split(0) == 171.588 && t.split(1) == 114.27 && t.split(4) == 72.7003)
    assert(t.leftIsLeaf(1) && t.rightIsLeaf(1) && !t.leftIsLeaf(0) && !t.rightIsLeaf(0))
    assert(t.levels == 3)
    assert(t.depth.toSeq == Seq(0, 1, 2, 2, 1, 2, 2))
  }

  /** A straightforward recursive build as the reference: immutable lists, Scala's stable sortBy,
    * returns the nodes in pre-order as (photon index, axis, left size, right size). */
  private def referenceBuild(pts: Array[Vec3], box: Box): Vector[(Int, Int, Int, Int)] = {
    def rec(ids: List[Int], lo: Vec3, hi: Vec3): Vector[(Int, Int, Int, Int)] = {
      if (ids.isEmpty) Vector.empty
      else {
        val e = hi - lo
        val a = if (e.x >= e.y && e.x >= e.z) 0 else if (e.y >= e.z) 1 else 2
        val sorted = ids.sortBy(pts(_)(a))
        val m = sorted.length / 2
        val s = pts(sorted(m))(a)
        def set(v: Vec3, value: Double) = a match {
          case 0 => v.copy(x = value); case 1 => v.copy(y = value); case _ => v.copy(z = value)
        }
        val (l, r) = (sorted.take(m), sorted.drop(m + 1))
        (sorted(m), a, l.length, r.length) +: (rec(l, lo, set(hi, s)) ++ rec(r, set(lo, s), hi))
      }
    }
    rec(pts.indices.toList, box.lo, box.hi)
  }

  test("random trees (with many tied coordinates) equal a straightforward recursive build") {
    val rnd = new scala.util.Random(11)
    for (trial <- 0 until 60) {
      val n = if (trial < 20) trial + 1 else rnd.nextInt(3000) + 1
      // coarse grid coordinates make ties common, which exercises the stable sort
      val grid = if (trial % 2 == 0) 8.0 else 1e6
      val pts = Array.fill(n)(Vec3((rnd.nextDouble() * grid).floor, (rnd.nextDouble() * grid * 0.7).floor, (rnd.nextDouble() * grid * 1.3).floor))
      val box = Box.of(pts.toSeq)
      val t = PhotonTree.build(pts, box)
      val ref = referenceBuild(pts, box)
      assert(ref.length == n)
      for (i <- 0 until n) {
        val (ph, a, nl, nr) = ref(i)
        assert(t.photon(i) == ph && t.axis(i) == a, s"trial $trial node $i")
        assert(t.hasLeft(i) == (nl > 0) && t.hasRight(i) == (nr > 0))
        assert(t.leftIsLeaf(i) == (nl == 1) && t.rightIsLeaf(i) == (nr == 1))
        if (nl > 0) assert(t.left(i) == i + 1)
        assert(t.right(i) == (if (nr > 0) i + 1 + nl else -1))
        assert(t.split(i) == pts(ph)(a) && t.position(i) == pts(ph))
      }
      // balanced: floor(log2 n) + 1 levels
      assert(t.levels == 32 - Integer.numberOfLeadingZeros(n), s"n = $n")
      assert(t.photon.sorted.toSeq == (0 until n))
    }
  }

  test("empty and one-photon trees; photons outside the box are rejected") {
    val box = Box(Vec3(0, 0, 0), Vec3(1, 2, 3))
    assert(PhotonTree.build(Array.empty[Vec3], box).size == 0)
    assert(PhotonTree.build(Array.empty[Vec3], box).levels == 0)
    val one = PhotonTree.build(Array(Vec3(0.5, 1, 1)), box)
    assert(one.size == 1 && one.isLeaf(0) && one.axis(0) == 2 && one.split(0) == 1.0 && one.levels == 1)
    val e = intercept[MapmError](PhotonTree.build(Array(Vec3(0.5, 1, 1), Vec3(2, 0, 0)), box))
    assert(e.getMessage.contains("photon 1") && e.getMessage.contains("outside"))
  }
}
