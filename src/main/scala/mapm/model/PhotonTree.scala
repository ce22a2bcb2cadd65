package mapm.model

import mapm.numerics._

import mapm.MapmError

/** The photon KD-tree (photon map) exactly as dissertation 3.1.4 builds it, stored as flat arrays
  * (struct of arrays) indexed by node number.
  *
  * Build rule, per node, starting from the given scene box at the root:
  *  - the split axis is the LONGEST axis of the node's box (ties: x, then y, then z);
  *  - the node's photons are STABLY sorted by their coordinate on that axis;
  *  - the photon in slot floor(n/2) stays in the node, slots below go to the left child and slots
  *    above to the right child, each keeping the sorted order;
  *  - the split value s is the node photon's coordinate on the split axis, and the child boxes end
  *    at s (left: hi(axis) = s, right: lo(axis) = s).
  * A node with one photon is a leaf. Nodes are numbered in pre-order: the left child of node i is
  * i+1 and the right child is i+1+size(left subtree). A node with two photons has a left child and
  * no right child; every other inner node has both.
  *
  * Leaves get an axis and split value by the same rule (from their own box); only a root leaf
  * (a one-photon tree) ever uses them, see [[TreeSearch]].
  *
  * Every left-subtree coordinate on the axis is <= s and every right-subtree one >= s. Rounding
  * to a float format is monotone, so this stays true after quantization; that is all the search
  * needs to find every photon closer than h.
  *
  * @param photon  index (into the build input) of the photon stored at each node
  * @param x       node photon positions, as given to the build
  * @param axis    split axis per node: 0 = x, 1 = y, 2 = z
  * @param split   split value per node (the node photon's coordinate on `axis`)
  * @param right   right child index, -1 when there is none (the left child is always i+1)
  * @param depth   depth per node (root 0)
  */
final class PhotonTree private (
    val photon: Array[Int],
    val x: Array[Double],
    val y: Array[Double],
    val z: Array[Double],
    val axis: Array[Byte],
    val split: Array[Double],
    val hasLeft: Array[Boolean],
    val hasRight: Array[Boolean],
    val leftIsLeaf: Array[Boolean],
    val rightIsLeaf: Array[Boolean],
    val right: Array[Int],
    val depth: Array[Int],
    val box: Box
) {
  /** Number of nodes, equal to the number of photons. */
  def size: Int = photon.length
  /** Left child index, -1 when there is none. */
  def left(i: Int): Int = if (hasLeft(i)) i + 1 else -1
  def isLeaf(i: Int): Boolean = !hasLeft(i) && !hasRight(i)
  /** Number of levels (0 for an empty tree, 1 for a single leaf); read after the build. */
  lazy val levels: Int = if (depth.isEmpty) 0 else depth.max + 1
  /** Node photon position. */
  def position(i: Int): Vec3 = Vec3(x(i), y(i), z(i))

  /** The [[NodeWord]] of node `i`. */
  def nodeWord(i: Int): Int =
    NodeWord.pack(axis(i), hasLeft(i), hasRight(i), leftIsLeaf(i), rightIsLeaf(i), if (hasRight(i)) right(i) else 0)

  /** The words of all nodes; a [[mapm.MapmError]] when the tree has more nodes than the word's index field holds. */
  def nodeWords: Array[Int] = {
    NodeWord.checkSize(size.toLong)
    Array.tabulate(size)(nodeWord)
  }
}

object PhotonTree {
  /** Axis letter for printing. */
  def axisName(a: Int): String = "xyz".substring(a, a + 1)

  /** Longest axis of a box; ties go to x, then y, then z. */
  def longestAxis(lo: Array[Double], hi: Array[Double]): Int = {
    val ex = hi(0) - lo(0); val ey = hi(1) - lo(1); val ez = hi(2) - lo(2)
    if (ex >= ey && ex >= ez) 0 else if (ey >= ez) 1 else 2
  }

  def build(photons: Array[Photon], box: Box): PhotonTree = build(photons.map(_.position), box)

  /** [[build]] with a progress bar over the nodes labelled `progress` when given. */
  def build(photons: Array[Photon], box: Box, progress: Option[String]): PhotonTree =
    Progress.maybe(progress, photons.length.toLong)(bar => build(photons.map(_.position), box, bar))

  /** Builds the tree over `positions` inside the root box `box`. Every position must be finite and
    * lie inside the box (a [[MapmError]] otherwise). `bar`, when given, advances by one per node. */
  def build(positions: Array[Vec3], box: Box, bar: Option[Progress] = None): PhotonTree = {
    val n = positions.length
    MapmError.check(box.lo.isFinite && box.hi.isFinite, s"photon tree: box $box is not finite")
    MapmError.check(box.lo.x <= box.hi.x && box.lo.y <= box.hi.y && box.lo.z <= box.hi.z, s"photon tree: box $box has lo > hi")
    var k = 0
    while (k < n) {
      val p = positions(k)
      MapmError.check(p.isFinite, s"photon tree: photon $k at $p is not finite")
      MapmError.check(box.contains(p), s"photon tree: photon $k at $p lies outside the box ${box.lo} .. ${box.hi}")
      k += 1
    }
    val coords = Array(positions.map(_.x), positions.map(_.y), positions.map(_.z))
    val t = new PhotonTree(
      new Array[Int](n), new Array[Double](n), new Array[Double](n), new Array[Double](n), new Array[Byte](n),
      new Array[Double](n), new Array[Boolean](n), new Array[Boolean](n), new Array[Boolean](n), new Array[Boolean](n),
      Array.fill(n)(-1), new Array[Int](n), box)
    val slots = Array.tabulate(n)(identity)
    val tmp = new Array[Int](n)
    val lo = Array(box.lo.x, box.lo.y, box.lo.z)
    val hi = Array(box.hi.x, box.hi.y, box.hi.z)

    // Builds the subtree of slots(from until until) as node `node`; the box is lo/hi (restored on return).
    def rec(node: Int, from: Int, until: Int, d: Int): Unit = {
      val cnt = until - from
      val a = longestAxis(lo, hi)
      val key = coords(a)
      stableSort(slots, tmp, from, until, key)
      val mid = from + cnt / 2
      val ph = slots(mid)
      val s = key(ph)
      t.photon(node) = ph
      t.x(node) = coords(0)(ph); t.y(node) = coords(1)(ph); t.z(node) = coords(2)(ph)
      t.axis(node) = a.toByte
      t.split(node) = s
      t.depth(node) = d
      bar.foreach(_.advance())
      val nLeft = mid - from
      val nRight = until - mid - 1
      if (nLeft > 0) {
        t.hasLeft(node) = true
        t.leftIsLeaf(node) = nLeft == 1
        val saved = hi(a); hi(a) = s
        rec(node + 1, from, mid, d + 1)
        hi(a) = saved
      }
      if (nRight > 0) {
        val r = node + 1 + nLeft
        t.hasRight(node) = true
        t.rightIsLeaf(node) = nRight == 1
        t.right(node) = r
        val saved = lo(a); lo(a) = s
        rec(r, mid + 1, until, d + 1)
        lo(a) = saved
      }
    }
    if (n > 0) rec(0, 0, n, 0)
    t
  }

  /** Stable merge sort of idx(from until until) by key(idx(_)), using tmp as scratch. */
  private def stableSort(idx: Array[Int], tmp: Array[Int], from: Int, until: Int, key: Array[Double]): Unit = {
    if (until - from < 2) return
    if (until - from <= 16) { // insertion sort: stable
      var i = from + 1
      while (i < until) {
        val v = idx(i); val kv = key(v)
        var j = i - 1
        while (j >= from && key(idx(j)) > kv) { idx(j + 1) = idx(j); j -= 1 }
        idx(j + 1) = v
        i += 1
      }
      return
    }
    val mid = (from + until) >>> 1
    stableSort(idx, tmp, from, mid, key)
    stableSort(idx, tmp, mid, until, key)
    if (key(idx(mid - 1)) <= key(idx(mid))) return
    System.arraycopy(idx, from, tmp, from, until - from)
    var i = from; var j = mid; var o = from
    while (i < mid && j < until) {
      if (key(tmp(j)) < key(tmp(i))) { idx(o) = tmp(j); j += 1 } else { idx(o) = tmp(i); i += 1 }
      o += 1
    }
    while (i < mid) { idx(o) = tmp(i); i += 1; o += 1 }
    while (j < until) { idx(o) = tmp(j); j += 1; o += 1 }
  }
}
