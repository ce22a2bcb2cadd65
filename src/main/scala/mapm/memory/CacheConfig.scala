package mapm.memory

import chisel3.util.{isPow2, log2Ceil}
import mapm.params.CacheParams

/** Everything that sizes one [[ReadOnlyCache]]: its geometry (a Table 4.2 row), the client word,
  * the lower port and the miss-handling resources.
  *
  * Associativity above `maxWays` is built as `maxWays`-way set-associative with the same capacity
  * and line size, with a hashed set index (docs/memory-port.md explains why a 4096-way CAM is not
  * built, and why the hash); geometries with at most `maxWays` lines stay fully associative.
  *
  * Set index: normally the line address modulo the set count. Hashed: the XOR of all set-index-wide
  * chunks of the line address (the lowest chunk XOR the next one XOR ...), which spreads the
  * power-of-two strides of a pre-order KD-tree over the sets; the tag stays the line address above
  * the lowest chunk, so a line is still identified by (set, tag).
  *
  * @param geometry    capacity, line size and associativity as specified
  * @param wordBytes   bytes per client read (8: a KD node, 32: a query record, an L1 line for an L2)
  * @param idBits      width of the client's opaque request id
  * @param addressBits byte-address width on both ports
  * @param downBytes   bytes per beat on the lower port (a line takes `lineBytes / downBytes` beats)
  * @param mshrs       misses in flight at once (miss-status holding registers)
  * @param targets     accesses that may wait on in-flight misses at once
  * @param maxWays     widest associativity built in hardware
  * @param counterBits width of the hit, miss and byte counters
  * @param hashSets    hash the set index (always done where associativity is capped at `maxWays`)
  * @param interleave  the cache is one of `interleave` banks that split the lines by their lowest
  *                    line-address bits (line address mod interleave); the set index skips those
  *                    bits so that every set is used, and the tag keeps them
  */
final case class CacheConfig(
    geometry: CacheParams,
    wordBytes: Int,
    idBits: Int,
    addressBits: Int = 32,
    downBytes: Int = 16,
    mshrs: Int = 4,
    targets: Int = 8,
    maxWays: Int = CacheParams.MaxWays,
    counterBits: Int = 40,
    hashSets: Boolean = false,
    interleave: Int = 1
) {
  require(isPow2(maxWays), s"cache maxWays must be a power of two, got $maxWays")
  require(isPow2(interleave), s"cache bank interleave must be a power of two, got $interleave")
  /** The geometry actually built: `geometry` with its associativity capped at `maxWays`. */
  val hw: CacheParams = if (geometry.ways > maxWays) geometry.copy(ways = maxWays) else geometry
  require(isPow2(hw.ways), s"cache associativity must be a power of two (tree pseudo-LRU), got ${hw.ways}")
  require(hw.lines >= 2, s"cache must hold at least two lines, got ${hw.lines}")
  require(isPow2(wordBytes) && wordBytes <= hw.lineBytes,
    s"cache client word must be a power of two of at most the line size ${hw.lineBytes} bytes, got $wordBytes")
  require(isPow2(downBytes) && downBytes <= hw.lineBytes,
    s"cache lower-port beat must be a power of two of at most the line size ${hw.lineBytes} bytes, got $downBytes")
  require(mshrs >= 1 && mshrs <= 64, s"cache MSHR count must be 1..64, got $mshrs")
  require(targets >= 1 && targets <= 64, s"cache target-table size must be 1..64, got $targets")
  require(counterBits >= 16 && counterBits <= 64, s"cache counter width must be 16..64, got $counterBits")
  require(addressBits > lineOffsetBits + setBits + bankBits, s"address width $addressBits leaves no tag bits for ${geometry.describe}")

  /** The set index is hashed: asked for, or standing in for a fully associative geometry. */
  def hashed: Boolean = (hashSets || geometry.ways > maxWays) && hw.sets > 1
  def ways: Int = hw.ways
  def sets: Int = hw.sets
  def lineBytes: Int = hw.lineBytes
  def lineOffsetBits: Int = log2Ceil(hw.lineBytes)
  def setBits: Int = log2Ceil(hw.sets)
  def tagBits: Int = addressBits - lineOffsetBits - setBits
  def wordsPerLine: Int = lineBytes / wordBytes
  def beatsPerLine: Int = lineBytes / downBytes
  /** Width of a word index within a line: none when a word is the whole line (an L2 under L1s of
    * its line size), so that no unused index port is left to lint. */
  def wordIdxBits: Int = log2Ceil(wordsPerLine)
  /** Width of a beat index (at least one bit). */
  def beatIdxBits: Int = log2Ceil(beatsPerLine) max 1
  /** Bits of the pseudo-LRU tree per set (none when direct mapped). */
  def plruBits: Int = ways - 1
  /** Index width of a data-array row (one line: set * ways + way). */
  def rowBits: Int = log2Ceil(hw.lines)
  def wayBits: Int = log2Ceil(ways) max 1
  /** Line-address bits below the set index that select the bank. */
  def bankBits: Int = log2Ceil(interleave)
  def mshrBits: Int = log2Ceil(mshrs) max 1

  /** The client port: single-beat reads of one word. */
  def up: MemPortParams = MemPortParams(addressBits, wordBytes, idBits)
  /** The lower port: whole-line reads of `beatsPerLine` beats, one id per MSHR. */
  def down: MemPortParams = MemPortParams(addressBits, downBytes, mshrBits, beatsPerLine)

  /** Module name with the geometry built, e.g. `ROCache_16k_l32_w2_r8` (r: client word bytes;
    * `w16x` for 16 ways with a hashed set index). */
  def name: String = {
    val size = if (hw.sizeBytes % 1024 == 0) s"${hw.sizeBytes / 1024}k" else s"${hw.sizeBytes}"
    s"ROCache_${size}_l${hw.lineBytes}_w${hw.ways}${if (hashed) "x" else ""}_r$wordBytes"
  }
}

object CacheConfig {
  /** A cache below `upper` (an L2 under an L1, or under an arbiter of L1s): its client word is the
    * upper port's single beat (the L1 line) and its client id is the upper port's id. */
  def below(upper: MemPortParams, geometry: CacheParams, downBytes: Int = 16, mshrs: Int = 8,
            targets: Int = 16, maxWays: Int = CacheParams.MaxWays): CacheConfig = {
    require(upper.maxBeats == 1, s"a cache serves single-beat requests; the upper port asks for up to ${upper.maxBeats} beats")
    CacheConfig(geometry, upper.dataBytes, upper.idBits, upper.addressBits, downBytes, mshrs, targets, maxWays)
  }
}
