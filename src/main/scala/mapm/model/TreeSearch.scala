package mapm.model

import mapm.numerics._

import mapm.MapmError

/** The two tree-search comparisons of dissertation 3.1.6 / 3.4.1, exact on their inputs:
  * TC_L = (p - h) < s and TC_R = (p + h) > s, strict, as real numbers.
  *
  * p, h and s are values of a float format, held exactly as doubles. The double sum d = p -/+ h is
  * rounded, but rounding is monotone and s is a double, so d < s or d > s already decides the
  * exact comparison; only d == s is ambiguous, and there the exact rounding error of the sum
  * (Knuth's TwoSum, exact in binary64 barring overflow) gives the answer by its sign. When the sum
  * overflows to an infinity the exact sum lies beyond every finite s, so the infinity still compares
  * correctly. The TSA hardware compares exactly, so the model does too.
  */
object TreeCompare {
  /** Exact (p - h) < s. */
  @inline def tcL(p: Double, h: Double, s: Double): Boolean = {
    val d = p - h
    if (d != s) d < s
    else { val bv = d - p; val err = (p - (d - bv)) + (-h - bv); err < 0 }
  }

  /** Exact (p + h) > s. */
  @inline def tcR(p: Double, h: Double, s: Double): Boolean = {
    val d = p + h
    if (d != s) d > s
    else { val bv = d - p; val err = (p - (d - bv)) + (h - bv); err > 0 }
  }
}

/** The search structure of one photon tree: per-node [[NodeWord]]s and split values (the exact
  * doubles of their format values). Shared, read-only, by any number of [[TreeSearcher]]s.
  * Stored side by side, `node(2i)` the split value's bits and `node(2i+1)` the word, so that a
  * tree-search operation reads one place in memory. */
final class SearchTree(words: Array[Int], splits: Array[Double]) {
  require(words.length == splits.length)
  val size: Int = words.length
  val node: Array[Long] = {
    val a = new Array[Long](2 * size)
    for (i <- 0 until size) { a(2 * i) = java.lang.Double.doubleToRawLongBits(splits(i)); a(2 * i + 1) = words(i).toLong }
    a
  }
  def word(i: Int): Int = node(2 * i + 1).toInt
  def split(i: Int): Double = java.lang.Double.longBitsToDouble(node(2 * i))
}

/** Runs tree searches for one query at a time, exactly as the pseudo code of dissertation 3.1.6 /
  * 3.4.1 (one instance per thread; it owns its scratch arrays, so a search allocates nothing).
  *
  * A query is launched at the root (node 0). Each visited node is one tree-search (TS) operation:
  * with p the query coordinate on the node's split axis,
  *  - if TC_L and the node has a left child: a non-leaf left child is queued for a TS, a leaf left
  *    child yields a shader operation (SO) for its photon;
  *  - the same for TC_R and the right child;
  *  - if TC_L and TC_R: an SO for the node's own photon.
  * Leaves therefore only ever arrive through SOs, never through a TS, with one exception: a
  * one-node tree, whose root is a leaf. The root is always searched as a node (it has an axis and a
  * split value like every node, and no children), so such a query yields an SO for the root photon
  * exactly when TC_L and TC_R hold, and one TS. An empty tree yields no operation at all.
  *
  * Pending searches are served first in, first out: breadth first, the order of the dissertation's
  * examples. The hardware keeps them in last-in first-out stacks (one Register-queue bank per TSM,
  * [[mapm.tsearch.RegisterStack]]) and searches depth first (docs/mapm.md, "Register queue rule"),
  * so its order differs; its TS and SO counts and its multiset of SOs equal the model's. After
  * [[search]], `visited(0 until tsCount)` holds the visited nodes in order, and
  * `so(0 until soCount)` the nodes whose photons got an SO, in issue order (per node: left child,
  * right child, current node).
  *
  * Every photon strictly closer than h to the query (on the exact values) gets an SO: along the
  * path to it each node's split value s lies between the query's coordinate interval and the
  * photon's coordinate, which makes the needed comparison true.
  */
final class TreeSearcher(tree: SearchTree) {
  /** Visited nodes in order; doubles as the first-in first-out queue of the pending searches (those
    * from the head on). Every node is queued at most once per query, so a search fills at most
    * `tree.size` of its slots. */
  val visited: Array[Int] = new Array[Int](tree.size + 1)
  /** Nodes that got an SO, in issue order (at most one SO per node per query, so at most
    * `tree.size` of its slots). */
  val so: Array[Int] = new Array[Int](tree.size + 1)
  var tsCount: Int = 0
  var soCount: Int = 0
  /** The query's coordinates by axis, so that a node's axis selects p by a load, not a branch. */
  private val coord = new Array[Double](3)

  /** Searches the tree for the query at (qx, qy, qz) with radius h (all exact format values): the
    * pseudo code's steps, a queued child appended at the queue's tail and an SO's node at the end
    * of `so`. */
  def search(qx: Double, qy: Double, qz: Double, h: Double): Unit = {
    val node = tree.node; val visited = this.visited; val so = this.so
    val coord = this.coord
    coord(0) = qx; coord(1) = qy; coord(2) = qz
    var nSo = 0
    var tail = 0
    if (node.length > 0) {
      visited(0) = 0
      tail = 1
      var head = 0
      while (head < tail) {
        val i = visited(head); head += 1
        val s = java.lang.Double.longBitsToDouble(node(2 * i))
        val w = node(2 * i + 1).toInt
        val p = coord(w & NodeWord.AxisMask)
        val tcl = TreeCompare.tcL(p, h, s)
        val tcr = TreeCompare.tcR(p, h, s)
        if (tcl && (w & NodeWord.HasLeft) != 0) {
          if ((w & NodeWord.LeftIsLeaf) != 0) { so(nSo) = i + 1; nSo += 1 }
          else { visited(tail) = i + 1; tail += 1 }
        }
        if (tcr && (w & NodeWord.HasRight) != 0) {
          val r = w >>> NodeWord.RightShift
          if ((w & NodeWord.RightIsLeaf) != 0) { so(nSo) = r; nSo += 1 }
          else { visited(tail) = r; tail += 1 }
        }
        if (tcl && tcr) { so(nSo) = i; nSo += 1 }
      }
    }
    tsCount = tail
    soCount = nSo
  }
}
