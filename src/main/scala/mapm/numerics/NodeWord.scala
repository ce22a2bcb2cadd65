package mapm.numerics

import mapm.MapmError

/** Packing of a KD node's structure into one 32-bit word. The model's tree search reads it
  * (`PhotonTree.nodeWords` builds a tree's words), and the memory image stores it as the second half of each 8-byte node record (docs/memory-layout.md).
  *
  * bits 1..0 split axis (0 = x, 1 = y, 2 = z); bit 2 has-left; bit 3 has-right; bit 4 left child is
  * a leaf; bit 5 right child is a leaf; bits 31..6 right child index (0 when there is none). The
  * left child, when present, is always the next node (pre-order numbering).
  */
object NodeWord {
  final val AxisMask = 3
  final val HasLeft = 1 << 2
  final val HasRight = 1 << 3
  final val LeftIsLeaf = 1 << 4
  final val RightIsLeaf = 1 << 5
  final val RightShift = 6
  /** Width of the right-child index field, and the most nodes a tree may have so that every index
    * fits it. */
  final val IndexBits = 32 - RightShift
  final val MaxNodes: Long = 1L << IndexBits

  def axis(w: Int): Int = w & AxisMask
  def right(w: Int): Int = w >>> RightShift

  /** The word of a node from its fields. */
  def pack(axis: Int, hasLeft: Boolean, hasRight: Boolean, leftIsLeaf: Boolean, rightIsLeaf: Boolean, right: Int): Int =
    axis | (if (hasLeft) HasLeft else 0) | (if (hasRight) HasRight else 0) | (if (leftIsLeaf) LeftIsLeaf else 0) |
      (if (rightIsLeaf) RightIsLeaf else 0) | (if (hasRight) right << RightShift else 0)

  /** A [[MapmError]] when a tree of `nodes` nodes has indices that the right-child field cannot hold. */
  def checkSize(nodes: Long): Unit =
    MapmError.check(nodes <= MaxNodes,
      s"photon tree has $nodes nodes; the node record's $IndexBits-bit right-child index holds at most $MaxNodes (one node per photon)")
}
