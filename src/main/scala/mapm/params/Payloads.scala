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

/** One tree-search instruction: the index of the query to run (its record holds the rest). */
class QueryIn(p: MapmParams) extends Bundle {
  val q = UInt(p.indices.queryBits.W)
}

/** Everything a search and its shader operations need of their query: position, contribution
  * and pixel (its record, read once through the SOQ cache when the query is issued) and index. */
class QueryData(p: MapmParams) extends Bundle {
  val x = UInt(p.numbers.format.width.W)
  val y = UInt(p.numbers.format.width.W)
  val z = UInt(p.numbers.format.width.W)
  val contrib = Vec(Rgb.Channels, UInt(p.numbers.format.width.W))
  val pixel = UInt(p.indices.pixelBits.W)
  val q = UInt(p.indices.queryBits.W)
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

  /** The SOM lane (SOA, SOP L1 bank) of a photon: its index mod `a` (the low bits for a power of
    * two, else the remainder digit by digit from the top: r = (2 r + bit) mod a, one
    * compare-subtract a bit). */
  def lane(photon: UInt, a: Int): UInt =
    if (a == 1) 0.U
    else if (isPow2(a)) photon(log2Ceil(a) - 1, 0)
    else {
      val w = log2Ceil(a)
      (photon.getWidth - 1 to 0 by -1).foldLeft(0.U(w.W)) { (r, i) =>
        val x = Cat(r, photon(i))
        Mux(x >= a.U, x - a.U, x)(w - 1, 0)
      }
    }

  /** How many of `g`'s SOs go to each of `a` lanes. */
  def needs(g: SoGroup, a: Int): Seq[UInt] =
    (0 until a).map(b => PopCount(g.photon.map(ph => ph.valid && lane(ph.bits, a) === b.U)))
}

/** The result of one shader operation: colour bits and flags per channel (OVF 1, UNF 2, INV 4),
  * the cond check, which query and photon it belongs to, and the query's pixel. */
class SoResult(p: MapmParams) extends Bundle {
  val colour = Vec(Rgb.Channels, UInt(p.numbers.format.width.W))
  val flags = Vec(Rgb.Channels, UInt(3.W))
  val cond = Bool()
  val pixel = UInt(p.indices.pixelBits.W)
  val q = UInt(p.indices.queryBits.W)
  val photon = UInt(p.indices.nodeBits.W)
}

import scala.language.dynamics

/** The counters the host reads at the end of a run (docs/mapm.md): 64 bits each, one per name of
  * [[MapmCounters.Names]] in that order (ports `io_counters_<name>`). A counter reads as a member,
  * `c.tsOps`; the harness header lists the same names ([[mapm.sim.HarnessHeader]]). */
class MapmCounters extends Record with scala.Dynamic {
  import scala.collection.immutable.SeqMap
  // Chisel emits a Record's ports in the reverse of its element order.
  val elements: SeqMap[String, UInt] = SeqMap.from(MapmCounters.Names.reverse.map(_ -> UInt(64.W)))

  /** The counter called `name`. */
  def selectDynamic(name: String): UInt =
    elements.getOrElse(name, throw new NoSuchElementException(s"MapmCounters has no counter $name"))
}

object MapmCounters {
  /** The counters' names, in port order (defined once in [[mapm.format.CounterSet]], where the
    * register map and the harness header read them too). */
  val Names: Seq[String] = mapm.format.CounterSet.Names
  /** What each counter counts. */
  val Units: Map[String, String] = mapm.format.CounterSet.Units
}
