package mapm.memory

import chisel3._
import chisel3.util._

/** Tree pseudo-LRU over a power-of-two number of ways (combinational helpers).
  *
  * The `ways - 1` state bits are the internal nodes of a complete binary tree in heap order: node
  * n (1-based; root 1, children 2n and 2n+1) is bit n-1. A node's bit names the subtree that holds
  * the next victim: 0 the lower-numbered half, 1 the upper half. Touching a way turns every node on
  * its path to point at the other half; the victim is found by following the bits from the root.
  * With two ways this is exact LRU; with one way there is no state (a zero-width `state`).
  */
object TreePlru {
  /** The way the state names as the next victim. */
  def victim(state: UInt, ways: Int): UInt = {
    if (ways == 1) 0.U(1.W)
    else {
      // Walk down from the root: at depth d the path so far (`prefix`, d bits) picks one of the
      // 2^d nodes of that depth, whose bit is the next bit of the victim's index.
      val first: UInt = state(0)
      (1 until log2Ceil(ways)).foldLeft(first) { (prefix: UInt, depth: Int) =>
        val level = VecInit((0 until (1 << depth)).map(i => state((1 << depth) + i - 1)))
        Cat(prefix, level(prefix))
      }
    }
  }

  /** The state after an access to `way`. */
  def touch(state: UInt, ways: Int, way: UInt): UInt = {
    if (ways == 1) state
    else {
      val levels = log2Ceil(ways)
      val bits = (1 until ways).map { node =>
        val depth = log2Floor(node)
        // `node` lies on the path of `way` when the top `depth` bits of the way equal node's low bits.
        val onPath = if (depth == 0) true.B else way(levels - 1, levels - depth) === (node - (1 << depth)).U
        val wentUpper = way(levels - 1 - depth)
        Mux(onPath, !wentUpper, state(node - 1))
      }
      VecInit(bits).asUInt
    }
  }
}
