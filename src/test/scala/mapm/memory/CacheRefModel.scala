package mapm.memory

import scala.collection.mutable

/** The replacement behaviour of [[ReadOnlyCache]] written independently, in plain Scala: accesses in
  * order, a miss fills the lowest-numbered empty way of its set, else the tree pseudo-LRU victim.
  *
  * With `hash` the set index is the XOR-folded line address ([[CacheConfig.hashed]]).
  *
  * The tree is walked over way ranges: a node covering ways [lo, hi) holds `true` when the next
  * victim lies in its upper half [mid, hi); an access sets every node on its path to the half it
  * did not take.
  */
final class RefCache(val sets: Int, val ways: Int, val lineBytes: Int, hash: Boolean = false) {
  /** The set of a line: its number modulo `sets`, or hashed: the XOR of its base-`sets` digits. */
  private def setOf(line: Long): Int =
    if (!hash) (line % sets).toInt
    else Iterator.iterate(line)(_ / sets).takeWhile(_ != 0).foldLeft(0L)((acc, x) => acc ^ (x % sets)).toInt

  private val tags = Array.fill(sets, ways)(-1L)
  private val upper = Array.fill(sets, (ways - 1) max 1)(false)
  var hits = 0L
  var misses = 0L
  /** Line addresses fetched, in miss order. */
  val fetched = mutable.ArrayBuffer[Long]()

  /** Looks up the byte address `addr`; true on a hit. */
  def access(addr: Long): Boolean = {
    val line = addr / lineBytes
    val set = setOf(line)
    val tag = line / sets
    val w = tags(set).indexOf(tag)
    if (w >= 0) { touch(set, w); hits += 1; true }
    else {
      val empty = tags(set).indexOf(-1L)
      val v = if (empty >= 0) empty else victim(set)
      tags(set)(v) = tag
      touch(set, v)
      misses += 1
      fetched += line * lineBytes
      false
    }
  }

  private def victim(set: Int): Int = {
    var (lo, hi, node) = (0, ways, 0)
    while (hi - lo > 1) {
      val mid = (lo + hi) / 2
      if (upper(set)(node)) { lo = mid; node = 2 * node + 2 } else { hi = mid; node = 2 * node + 1 }
    }
    lo
  }

  private def touch(set: Int, way: Int): Unit = {
    var (lo, hi, node) = (0, ways, 0)
    while (hi - lo > 1) {
      val mid = (lo + hi) / 2
      val inUpper = way >= mid
      upper(set)(node) = !inUpper
      if (inUpper) { lo = mid; node = 2 * node + 2 } else { hi = mid; node = 2 * node + 1 }
    }
  }
}

object RefCache {
  def apply(cfg: CacheConfig): RefCache = new RefCache(cfg.sets, cfg.ways, cfg.lineBytes, cfg.hashed)
}

/** A cache with true LRU replacement, or FIFO replacement (the behaviour the dissertation describes
  * for the SOQ cache), counting misses; `sets = 1` makes it fully associative. */
final class RefLruCache(sets: Int, ways: Int, lineBytes: Int, lru: Boolean = true) {
  private val order = Array.fill(sets)(mutable.LinkedHashSet[Long]())
  var misses = 0L
  def access(addr: Long): Boolean = {
    val line = addr / lineBytes
    val o = order((line % sets).toInt)
    if (o.contains(line)) {
      if (lru) { o -= line; o += line }
      true
    } else {
      if (o.size == ways) o -= o.head
      o += line
      misses += 1
      false
    }
  }
}
