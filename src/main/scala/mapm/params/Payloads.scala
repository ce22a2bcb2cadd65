package mapm.params

import chisel3._
import chisel3.util._

/** Run-time configuration of one MAPM, held constant for a whole frame (docs/mapm.md). */
class MapmConfig(p: MapmParams) extends Bundle {
  /** Kernel radius h: format bits. */
  val h = UInt(p.numbers.format.width.W)
  /** Byte address of node record 0 (8-byte records). */
  val nodeBase = UInt(p.memory.addressBits.W)
  /** Byte address of photon record 0 (32-byte records, node order). */
  val photonBase = UInt(p.memory.addressBits.W)
  /** Byte address of query record 0 (32-byte records). */
  val queryBase = UInt(p.memory.addressBits.W)
  /** Nodes in the photon tree (0 = empty tree: every query finishes with no operation). */
  val nodeCount = UInt((p.indices.nodeBits + 1).W)
}

/** One tree-search instruction from the host: the query's position and index. */
class QueryIn(p: MapmParams) extends Bundle {
  val x = UInt(p.numbers.format.width.W)
  val y = UInt(p.numbers.format.width.W)
  val z = UInt(p.numbers.format.width.W)
  val q = UInt(p.indices.queryBits.W)
}

/** Everything a search and its shader operations need of their query: position, contribution
  * (read once from the SOQ cache when the query is issued) and index. */
class QueryData(p: MapmParams) extends Bundle {
  val x = UInt(p.numbers.format.width.W)
  val y = UInt(p.numbers.format.width.W)
  val z = UInt(p.numbers.format.width.W)
  val contrib = Vec(Rgb.Channels, UInt(p.numbers.format.width.W))
  val q = UInt(p.indices.queryBits.W)
}

/** One shader operation: a query and the photon of node `photon`. */
class SoOp(p: MapmParams) extends Bundle {
  val query = new QueryData(p)
  val photon = UInt(p.indices.nodeBits.W)
}

/** The shader operations of one tree-search operation, in Nextnode's order: left child, right
  * child, current node, with the query they share. They move as one: a handshake hands over every
  * valid photon at once. */
class SoGroup(p: MapmParams) extends Bundle {
  val query = new QueryData(p)
  val photon = Vec(SoGroup.Size, Valid(UInt(p.indices.nodeBits.W)))
}

object SoGroup {
  /** Shader operations in a group, at most: a tree-search operation's left child, right child
    * and current node. */
  val Size = 3
}

/** The result of one shader operation: colour bits and flags per channel (OVF 1, UNF 2, INV 4),
  * the cond check, and which query and photon it belongs to. */
class SoResult(p: MapmParams) extends Bundle {
  val colour = Vec(Rgb.Channels, UInt(p.numbers.format.width.W))
  val flags = Vec(Rgb.Channels, UInt(3.W))
  val cond = Bool()
  val q = UInt(p.indices.queryBits.W)
  val photon = UInt(p.indices.nodeBits.W)
}

/** The counters the host reads at the end of a run (docs/mapm.md): 64 bits each. */
class MapmCounters extends Bundle {
  val cycles = UInt(64.W)
  val queries = UInt(64.W)
  val tsOps = UInt(64.W)
  val soIssued = UInt(64.W)
  val soPassed = UInt(64.W)
  val stallNodeData = UInt(64.W)
  val stallRsFull = UInt(64.W)
  val stallRqFull = UInt(64.W)
  val stallQuery = UInt(64.W)
  val tsL1_hits = UInt(64.W)
  val tsL1_misses = UInt(64.W)
  val tsL2_hits = UInt(64.W)
  val tsL2_misses = UInt(64.W)
  val soq_hits = UInt(64.W)
  val soq_misses = UInt(64.W)
  val sopL1_hits = UInt(64.W)
  val sopL1_misses = UInt(64.W)
  val sopL2_hits = UInt(64.W)
  val sopL2_misses = UInt(64.W)
  val bytesFetched = UInt(64.W)
  /** Largest occupancy any TSM's Register-queue bank reached (the overflow rule's witness). */
  val rqPeak = UInt(64.W)
}
