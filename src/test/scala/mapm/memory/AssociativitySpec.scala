package mapm.memory

import mapm.Slow
import mapm.model.{Box, PhotonTree, SearchTree, TreeSearcher}
import mapm.numerics.{NodeWord, Vec3}
import mapm.params.{CacheParams, CachesParams, MemoryParams}
import org.scalatest.funsuite.AnyFunSuite
import scala.util.Random

/** Why Table 4.2's fully associative L2s are built 16-way set-associative with a hashed set index
  * (docs/memory-port.md), on the reference models (no hardware involved). */
@Slow
class AssociativitySpec extends AnyFunSuite {
  private val t42 = CachesParams()
  private def built(g: CacheParams) = CacheConfig(g, 32, 4, MemoryParams().addressBits).hw

  test("the L2s are built 16-way with the same capacity and line and a hashed set index") {
    for (g <- Seq(t42.tsL2, t42.sopL2)) {
      val cfg = CacheConfig(g, 32, 4, MemoryParams().addressBits)
      assert(g.fullyAssociative && cfg.ways == 16 && cfg.hw.sizeBytes == g.sizeBytes && cfg.lineBytes == g.lineBytes)
      assert(cfg.hashed && cfg.name.contains("_w16x_"))
    }
    assert(built(CacheParams(512, 64, 8)).fullyAssociative, "small fully associative caches stay so")
    assert(!CacheConfig(t42.tsL1, 8, 4).hashed && !CacheConfig(t42.soq, 32, 4).hashed, "the L1s and the SOQ cache index by modulo")
  }

  test("arrays that fit the L2 (the case Table 4.2 is sized for) cause no conflict misses: only compulsory ones") {
    val rnd = new Random(1)
    for (_ <- 0 until 12) {
      // TS L2: the KD-node array (8-byte nodes) at a random 8-byte aligned base, up to 15/16 of the
      // capacity. SOP L2: the photon-record array (16 bytes each) and a parameter array beside it.
      val (g, arrays) =
        if (rnd.nextBoolean()) {
          val bytes = 8 * (1 + rnd.nextInt(t42.tsL2.sizeBytes / 16 * 15 / 8))
          (t42.tsL2, Seq((8L * rnd.nextInt(1 << 20), bytes)))
        } else {
          val photons = 16 * (1 + rnd.nextInt(t42.sopL2.sizeBytes / 2 / 16))
          val params = 8 * (1 + rnd.nextInt(t42.sopL2.sizeBytes / 4 / 8))
          val base = 16L * rnd.nextInt(1 << 20)
          (t42.sopL2, Seq((base, photons), (base + photons + 64 * rnd.nextInt(1000), params)))
        }
      val ref = RefCache(CacheConfig(g, 32, 4, MemoryParams().addressBits))
      val lines = arrays.flatMap { case (b, n) => (b / g.lineBytes) to ((b + n - 1) / g.lineBytes) }.distinct.size
      for (_ <- 0 until 300000) {
        val (b, n) = arrays(rnd.nextInt(arrays.size))
        ref.access(b + rnd.nextInt(n))
      }
      assert(ref.misses == lines, s"${g.describe}: ${ref.misses} misses for $lines lines of ${arrays.map(_._2).sum} bytes")
    }
  }

  test("tree searches over a KD tree twice the TS L2: the hashed 16-way cache within 5% of fully associative LRU") {
    val rnd = new Random(7)
    val photons = 65536 // 512 KiB of 8-byte nodes, twice the 256 KiB TS L2
    val pos = Array.fill(photons)(Vec3(rnd.nextDouble(), rnd.nextDouble(), 0.2 * rnd.nextDouble()))
    val tree = PhotonTree.build(pos, Box(Vec3(0, 0, 0), Vec3(1, 1, 0.2)))
    val searcher = new TreeSearcher(new SearchTree(tree.nodeWords, tree.split))
    val g = t42.tsL2
    // Queries in scan order (pixels, as the CPU launches them), then in random order (no locality).
    val side = 160
    val scan = for (py <- 0 until side; px <- 0 until side) yield ((px + rnd.nextDouble()) / side, (py + rnd.nextDouble()) / side)
    for ((order, queries) <- Seq("scan order" -> scan, "random order" -> rnd.shuffle(scan))) {
      val built16 = RefCache(CacheConfig(g, 8, 4, MemoryParams().addressBits))
      val modulo16 = new RefCache(g.lines / 16, 16, g.lineBytes)
      val faLru = new RefLruCache(1, g.lines, g.lineBytes)
      var reads = 0L
      for ((qx, qy) <- queries) {
        searcher.search(qx, qy, 0.2 * rnd.nextDouble(), 0.02)
        for (k <- 0 until searcher.tsCount) {
          val a = 8L * searcher.visited(k)
          built16.access(a); modulo16.access(a); faLru.access(a)
          reads += 1
        }
      }
      info(s"$order, $reads node reads: misses fully associative LRU ${faLru.misses}, " +
        s"16-way pseudo-LRU hashed index (built) ${built16.misses}, modulo index ${modulo16.misses}")
      assert(built16.misses <= faLru.misses * 105 / 100, s"$order: ${built16.misses} misses, fully associative LRU ${faLru.misses}")
    }
  }
}
