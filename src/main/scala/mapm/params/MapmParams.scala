package mapm.params

import chisel3.util.isPow2
import mapm.format.{MemoryLayout, SlotLayout}
import mapm.numerics.{Arith, FloatFormat}

/** The colour channels of a photon's power, a query's contribution and a shader operation's
  * colour: r, g, b, in this order everywhere. */
object Rgb {
  val Names: Seq[String] = Seq("r", "g", "b")
  val Channels: Int = Names.size
}

/** Geometry of one read-only cache.
  *
  * @param sizeBytes total data capacity in bytes
  * @param lineBytes bytes per line
  * @param ways      associativity (1 = direct mapped; `lines` = fully associative)
  */
final case class CacheParams(
    sizeBytes: Int = 16 * 1024, // total data bytes
    lineBytes: Int = 32,        // bytes per line
    ways: Int = 2               // associativity; 1 = direct mapped
) {
  require(isPow2(lineBytes) && lineBytes >= 8, s"cache line must be a power of two of at least 8 bytes, got $lineBytes")
  require(sizeBytes >= lineBytes && sizeBytes % lineBytes == 0, s"cache size $sizeBytes must be a positive multiple of the line size $lineBytes")
  require(ways >= 1 && lines % ways == 0, s"cache ways $ways must divide the line count $lines")
  require(isPow2(sets), s"cache set count must be a power of two, got $sets (size $sizeBytes, line $lineBytes, ways $ways)")
  require(lines >= 2, s"cache must hold at least two lines, got $lines (size $sizeBytes, line $lineBytes)")
  require(isPow2(hwWays) && isPow2(lines / hwWays), s"cache of $lines lines, ${if (fullyAssociative) "fully associative" else s"$ways-way"}: " +
    s"the hardware builds at most ${CacheParams.MaxWays} power-of-two ways over a power-of-two set count (size $sizeBytes, line $lineBytes)")

  /** The ways the hardware builds: at most [[CacheParams.MaxWays]]; a higher associativity (fully
    * associative included) is built as that many ways over a hashed set index (docs/memory-port.md). */
  def hwWays: Int = math.min(ways, CacheParams.MaxWays)

  /** Number of lines and of sets. */
  def lines: Int = sizeBytes / lineBytes
  def sets: Int = lines / ways
  def fullyAssociative: Boolean = sets == 1
  def describe: String = s"${sizeBytes / 1024} KiB, $lineBytes B lines, ${if (fullyAssociative) "fully associative" else s"$ways-way"}"
}

object CacheParams {
  /** The most ways the hardware's caches build (their pseudo-LRU tree and tag compare). */
  val MaxWays: Int = 16
}

/** The five caches of Table 4.2. */
final case class CachesParams(
    tsL1: CacheParams = CacheParams(16 * 1024, 32, 2),              // Tree Search L1, per TSM
    tsL2: CacheParams = CacheParams(256 * 1024, 64, 256 * 1024 / 64), // Tree Search L2, shared, fully associative
    soq: CacheParams = CacheParams(16 * 1024, 32, 1),               // Shader Operation query cache, direct mapped (FIFO-like)
    sopL1: CacheParams = CacheParams(64 * 1024, 32, 2),             // Shader Operation photon L1, per SOM
    sopL2: CacheParams = CacheParams(512 * 1024, 64, 512 * 1024 / 64) // Shader Operation photon L2, shared, fully associative
)

/** How many of each replicable module (Figure 4.8). */
final case class ModuleCounts(
    tsm: Int = 16,  // Tree Search Modules (each with one TSA)
    som: Int = 16,  // Shader Operation Modules
    soaPerSom: Int = 2 // Shader Operation Accelerators in each SOM
) {
  require(tsm >= 1 && tsm <= ModuleCounts.MaxTsm, s"--tsm (TSM count) must be 1..${ModuleCounts.MaxTsm}, got $tsm")
  require(som >= 1 && som <= ModuleCounts.MaxSom, s"--som (SOM count) must be 1..${ModuleCounts.MaxSom}, got $som")
  require(soaPerSom >= 1 && soaPerSom <= ModuleCounts.MaxSoaPerSom, s"--soa (SOAs per SOM) must be 1..${ModuleCounts.MaxSoaPerSom}, got $soaPerSom")
  def label: String = s"$tsm/$som/$soaPerSom"
}

object ModuleCounts {
  /** The largest counts the generator takes. The memory-port ids grow with them (the TS L2 and
    * SOP L2 tag each request with its requester's index) and still fit their 16 bits here
    * (LimitsSpec checks it); 100,000 TSMs would not. */
  val MaxTsm = 1024
  val MaxSom = 1024
  val MaxSoaPerSom = 16
}

/** Number format of every value the accelerator computes on. */
final case class NumberParams(
    format: FloatFormat = FloatFormat.fp32, // float format of positions, h, split values, power, ...
    guardDigits: Int = 3,                   // extra online digits in the SOA (0 = the dissertation's design)
    fpuStageWeight: Double = NumberParams.DefaultFpuStageWeight, // logic per register stage of the conventional FP units (docs/fpu.md)
    arith: Arith = Arith.Online             // the SOAs' colour chain and the TSAs: online, or the conventional baseline
) {
  require(guardDigits >= 0 && guardDigits <= 8, s"guard digits must be 0..8, got $guardDigits")
  require(fpuStageWeight >= 0.5 && fpuStageWeight <= 100, s"FPU logic per stage must be 0.5..100, got $fpuStageWeight")
  require(arith != Arith.Online || format.manWidth >= 4,
    s"the online SOA needs at least 4 fraction bits (n >= 5), format $format has ${format.manWidth}")
}

object NumberParams {
  /** Logic per register stage of the conventional floating-point units, in their steps' weight
    * units (about one full adder each; docs/fpu.md): the fp32 cond check at this weight measured
    * 467 to 510 MHz on OSU018 (docs/cost.md), above the online SOA's clock. */
  val DefaultFpuStageWeight: Double = 2.0
}

/** Queues and buffers between the blocks (docs/mapm.md explains each). */
final case class QueueParams(
    registerQueueDepth: Int = 256, // entries of each TSM's bank of the Register queue (pending child searches)
    rsEntries: Int = 16,           // reservation-station entries per SOM, split evenly among its SOAs
    fetchSlots: Int = 16,          // node fetches one TSM keeps in flight (its non-blocking window before the TSA)
    tsmQueries: Int = 32,          // queries one TSM searches at once (its query table)
    queryFetches: Int = 64         // new queries whose SOQ record is being fetched at once (covers the memory latency)
) {
  require(registerQueueDepth >= 8 && registerQueueDepth <= 4096, s"Register queue depth must be 8..4096 per TSM, got $registerQueueDepth")
  require(rsEntries >= SoGroup.Size, s"reservation-station entries must be at least ${SoGroup.Size} (one SO group), got $rsEntries")
  require(fetchSlots >= 1 && fetchSlots <= 64, s"TSM fetch slots must be 1..64, got $fetchSlots")
  require(tsmQueries >= 1 && tsmQueries <= 256, s"queries per TSM must be 1..256, got $tsmQueries")
  require(queryFetches >= 1 && queryFetches <= 64, s"query fetches must be 1..64, got $queryFetches")
}

/** The memory port shared by all caches. */
final case class MemoryParams(
    dataBytes: Int = 16,      // bytes per response beat
    maxOutstanding: Int = 64, // requests in flight at once on the memory port (the outermost MemArbiter's limit)
    addressBits: Int = 32,    // byte address width
    layout: SlotLayout = SlotLayout.Packed // format slots of the memory records: packed (2, 4 or 8 bytes) or wide (at least 4)
) {
  require(dataBytes >= 4 && isPow2(dataBytes), s"memory data width must be a power of two of at least 4 bytes, got $dataBytes")
  require(maxOutstanding >= 1, s"outstanding-request limit must be at least 1, got $maxOutstanding")
  require(addressBits >= 16 && addressBits <= 48, s"address width must be 16..48 bits, got $addressBits")
}

/** Widths of the indices that travel with operations. */
final case class IndexParams(
    queryBits: Int = 24, // query index width: up to 16 M queries per frame
    nodeBits: Int = 22,  // photon-tree node index width: up to 4 M photons
    pixelBits: Int = 24  // pixel index width: up to 16 M pixels per frame
) {
  require(queryBits >= 1 && queryBits <= 31, s"query index width must be 1..31, got $queryBits")
  require(nodeBits >= 1 && nodeBits <= 26, s"node index width must be 1..26 (the 8-byte node record's right-child field), got $nodeBits")
  require(pixelBits >= 1 && pixelBits <= 32, s"pixel index width must be 1..32 (the query record's pixel field), got $pixelBits")
}

/** What the emitted SOAs compute: `full` (the arithmetic, colours and the distance check) or
  * `timing` (a latency-exact delay line carrying valid and tag alone: cycle for cycle the same
  * machine, colours and cond left to the harness's expected SOs; docs/harness.md). */
sealed abstract class Fidelity(name: String) extends mapm.Choice(name)
object Fidelity extends mapm.Choices[Fidelity] {
  case object Full extends Fidelity("full")
  case object Timing extends Fidelity("timing")
  val all: Seq[Fidelity] = Seq(Full, Timing)
  protected def unknown(s: String): String = s"fidelity must be one of ${all.map(_.name).mkString(", ")}, got '$s'"
}

/** How a shared L2 is built: one cache with one port (Table 4.2's), or `banks` caches that split
  * the lines by address, each with its own port, behind a registered network (docs/uncore.md). */
sealed abstract class L2Structure(name: String) extends mapm.Choice(name) {
  /** The caches it is built of. */
  def banks: Int
}
object L2Structure {
  /** Whether an L2 of geometry `g` splits into `banks` banks: two lines and a set a bank. */
  def splits(g: CacheParams, banks: Int): Boolean = g.lines / banks >= 2 && (g.fullyAssociative || g.sets >= banks)
  /** One cache, one request a cycle: the dissertation's shared L2. */
  case object Shared extends L2Structure("shared") { val banks = 1 }
  /** `banks` address-interleaved caches (line address mod `banks`), each a quarter, an eighth ... of
    * the capacity, each taking one request a cycle. */
  final case class Banked(banks: Int) extends L2Structure(s"banked$banks") {
    require(banks >= 2 && banks <= Banked.MaxBanks && isPow2(banks), s"L2 banks must be a power of two 2..${Banked.MaxBanks}, got $banks")
  }
  object Banked {
    val MaxBanks = 64
  }
}

/** How the Data bus hands the TSMs' SO groups to the SOMs (mapm.uncore, docs/mapm.md). */
sealed abstract class SoBus(name: String) extends mapm.Choice(name) {
  /** Reservation-station entries per SOA that a configuration left at its default gets on top of
    * it, to cover the cycles between a group's grant and its SOM and between an entry's issue and
    * its credit (docs/mapm.md, "The ring bus"). */
  def extraRsPerSoa: Int
}
object SoBus extends mapm.Choices[SoBus] {
  /** The dissertation's (3.2): in one cycle, the groups claim SOMs with room one TSM after another
    * (t x s logic, a combinational path from a SOM lane's free count to a TSM's stall). */
  case object Serial extends SoBus("serial") { val extraRsPerSoa = 0 }
  /** A ring of credit tokens and a registered rotation (N log N logic, N = max(t, s); every stage
    * registered; a group reaches its SOM a cycle after its grant). */
  case object Ring extends SoBus("ring") { val extraRsPerSoa = 2 }
  val all: Seq[SoBus] = Seq(Ring, Serial)
  protected def unknown(s: String): String = s"Data bus must be ${all.mkString(" or ")}, got '$s'"
}

/** The memory system between the blocks' L1s and the memory port, and the Data bus (mapm.uncore). */
final case class UncoreParams(
    tsL2: L2Structure = L2Structure.Shared, // the TS L2: one shared cache, or address-interleaved banks
    sopL2: L2Structure = L2Structure.Shared, // the SOP L2: one shared cache, or address-interleaved banks
    soBus: SoBus = SoBus.Serial              // the Data bus: the dissertation's serial claims (Table 4.2's hierarchy), or the staged ring (the scalable one's)
)

/** The memory hierarchy a configuration is built with: the dissertation's (Table 4.2: one shared
  * TS L2 and one shared SOP L2, each taking one request a cycle, a direct-mapped SOQ cache) or
  * this project's scalable one (docs/uncore.md: the SOP L2 in address-interleaved banks, one per
  * two SOP L1 banks, a 4-way SOQ cache and TS L1s of 64-byte lines), which keeps a 16/16/2 busy
  * once the photon map no longer fits its SOP L1s. Both keep Table 4.2's capacities. */
sealed abstract class Hierarchy(name: String) extends mapm.Choice(name) {
  /** The SOQ cache's geometry. */
  def soq: CacheParams
  /** Each TSM's TS L1's geometry. */
  def tsL1: CacheParams
  /** The L2 structures for module counts `c` and an SOP L2 of geometry `sopL2`. */
  def uncore(c: ModuleCounts, sopL2: CacheParams): UncoreParams
  /** `p` with this hierarchy's L2 structures, Data bus, SOQ and TS L1 geometries, for `p`'s module
    * counts and SOP L2; the reservation stations gain or lose what the bus asks for a SOA
    * ([[SoBus.extraRsPerSoa]]), as the command line's configurations do. */
  def apply(p: MapmParams): MapmParams = {
    val u = uncore(p.counts, p.caches.sopL2)
    val rs = p.queues.rsEntries + (u.soBus.extraRsPerSoa - p.uncore.soBus.extraRsPerSoa) * p.counts.soaPerSom
    p.copy(caches = p.caches.copy(soq = soq, tsL1 = tsL1), uncore = u, queues = p.queues.copy(rsEntries = rs))
  }
}
object Hierarchy extends mapm.Choices[Hierarchy] {
  case object Table42 extends Hierarchy("table4.2") {
    val soq: CacheParams = CachesParams().soq
    val tsL1: CacheParams = CachesParams().tsL1
    def uncore(c: ModuleCounts, sopL2: CacheParams): UncoreParams = UncoreParams()
  }
  case object Scalable extends Hierarchy("scalable") {
    /** The SOQ cache: Table 4.2's capacity and line, 4-way. Every query record is read once, out of
      * order when the host streams its queries in Morton order; a direct-mapped SOQ stalls its
      * lookup whenever a read's set still waits for another record (docs/uncore.md). */
    val soq: CacheParams = CacheParams(16 * 1024, 32, 4)
    /** The TS L1: Table 4.2's capacity and ways, 64-byte lines (the TS L2's). The KD tree is stored
      * depth first, so a line holds a node's left subtree's next nodes: on the 8k-photon Cornell box
      * at 16/16/2 the longer line cuts the TS L1's misses by 43 % and the TSMs' node-data waits by
      * 84 % (docs/uncore.md), with half the tags. */
    val tsL1: CacheParams = CacheParams(16 * 1024, 64, 2)
    /** SOP L2 banks: one per two SOP L1 banks, rounded down to a power of two (so shared below
      * four SOP L1 banks), at most [[L2Structure.Banked.MaxBanks]] and at most what the SOP L2's
      * geometry `g` splits into (two lines and a set a bank). */
    def sopL2Banks(c: ModuleCounts, g: CacheParams): Int = {
      val want = math.min(L2Structure.Banked.MaxBanks, Integer.highestOneBit(math.max(1, c.som * c.soaPerSom / 2)))
      Iterator.iterate(want)(_ / 2).find(n => n == 1 || L2Structure.splits(g, n)).get
    }
    def uncore(c: ModuleCounts, sopL2: CacheParams): UncoreParams = {
      val n = sopL2Banks(c, sopL2)
      UncoreParams(sopL2 = if (n == 1) L2Structure.Shared else L2Structure.Banked(n), soBus = SoBus.Ring)
    }
  }
  val all: Seq[Hierarchy] = Seq(Scalable, Table42)
  protected def unknown(s: String): String = s"memory hierarchy must be ${all.mkString(" or ")}, got '$s'"
}

/** Clock gating, which saves the power of idle logic in silicon and its evaluation in Verilator. */
final case class ClockingParams(
    soaClockGate: Boolean = true,  // each SOA's clock runs only while an operation enters or is inside it (docs/mapm.md)
    soaStageGate: Boolean = true   // inside an SOA, each pipeline stage's clock runs only when it takes an operation (docs/soa.md)
)

/** The coprocessor around the MAPM (docs/coprocessor.md): its frame accumulator and its AXI4 port. */
final case class CoprocParams(
    tileLog2: Int = 13,     // a frame pass covers at most 2^tileLog2 pixels (8192: the 75 x 60 frames in one pass)
    accBits: Int = 0,       // bits of a pixel channel's fixed-point sum; 0: 64 up to 32-bit formats, 128 above
    countBits: Int = 24,    // bits of a pixel's contribution count (at most 2^24 - 1 contributions a pixel)
    banks: Int = 0,         // accumulator banks (a power of two); 0: one per SOA (rounded down to a power of two)
    laneFifo: Int = 0,      // result FIFO entries per SOA lane; 0: the lane's RS entries + its SOA's latency + 32
    axiIdBits: Int = 0,     // AXI4 id width; 0: as many as the reads need (the MAPM's memory port's, plus one)
    streamLines: Int = 4    // 64-byte lines of the query stream read ahead
) {
  require(tileLog2 >= 4 && tileLog2 <= 24, s"frame tile must be 2^4..2^24 pixels, got 2^$tileLog2")
  require(accBits == 0 || (accBits >= 32 && accBits <= 128), s"frame sums must be 32..128 bits (or 0: by the format), got $accBits")
  require(countBits >= 4 && countBits <= 32, s"frame counts must be 4..32 bits, got $countBits")
  require(banks == 0 || (banks >= 1 && isPow2(banks) && banks <= (1 << tileLog2)), s"frame accumulator banks must be a power of two up to the tile's pixels (or 0: by the SOA count), got $banks")
  require(laneFifo == 0 || laneFifo >= 4, s"result FIFO must hold at least 4 entries (or 0: by the SOA's latency), got $laneFifo")
  require(axiIdBits == 0 || (axiIdBits >= 2 && axiIdBits <= 10), s"AXI4 id width must be 2..10 bits (or 0: as the reads need), got $axiIdBits")
  require(streamLines >= 1 && streamLines <= 64, s"query-stream read-ahead must be 1..64 lines, got $streamLines")
}

/** How the emitted design is meant to be simulated. */
final case class SimParams(
    fidelity: Fidelity = Fidelity.Full, // full RTL, or SOAs replaced by their timing model
    coproc: Boolean = false             // simulate the coprocessor around the MAPM (docs/coprocessor.md), not the bare MAPM
)

/** Everything that sizes one MAPM instance. Every field has a default; presets below. */
final case class MapmParams(
    counts: ModuleCounts = ModuleCounts(),   // TSM / SOM / SOA counts
    numbers: NumberParams = NumberParams(),  // float format and guard digits
    queues: QueueParams = QueueParams(),     // Register queue and reservation stations
    caches: CachesParams = CachesParams(),   // cache geometry (Table 4.2)
    memory: MemoryParams = MemoryParams(),   // memory port
    indices: IndexParams = IndexParams(),    // index widths
    clocking: ClockingParams = ClockingParams(), // clock gating
    uncore: UncoreParams = UncoreParams(),   // the L2s and the memory system below the L1s
    sim: SimParams = SimParams(),            // full RTL or the SOAs' timing model
    coproc: CoprocParams = CoprocParams()    // the coprocessor's frame accumulator and AXI4 port
) {
  /** Bytes of a format slot in the memory records: the format's in the configured layout. */
  def slotBytes: Int = memory.layout.slotBytes(numbers.format)
  /** The memory records the hardware reads, at [[slotBytes]]. */
  lazy val records: Records = new Records(slotBytes)

  require(caches.tsL1.lineBytes <= caches.tsL2.lineBytes, "TS L1 line must not be longer than the TS L2 line")
  for ((name, c) <- Seq("TS L1" -> caches.tsL1, "TS L2" -> caches.tsL2, "SOQ" -> caches.soq, "SOP L1" -> caches.sopL1, "SOP L2" -> caches.sopL2))
    require(c.lineBytes <= MemoryLayout.Alignment,
      s"$name line of ${c.lineBytes} bytes is longer than the memory image's ${MemoryLayout.Alignment}-byte array alignment: a line read could reach past an array")
  require(caches.tsL1.lineBytes >= records.node.bytes,
    s"TS L1 line of ${caches.tsL1.lineBytes} bytes is shorter than a ${records.node.bytes}-byte node record ($slotBytes-byte slots)")
  require(caches.soq.lineBytes >= records.queryHwBytes,
    s"SOQ line of ${caches.soq.lineBytes} bytes is shorter than the ${records.queryHwBytes} bytes of a query record it reads ($slotBytes-byte slots)")
  require(caches.sopL1.lineBytes >= records.photon.bytes,
    s"SOP L1 line of ${caches.sopL1.lineBytes} bytes is shorter than a ${records.photon.bytes}-byte photon record ($slotBytes-byte slots)")
  require(caches.sopL1.lineBytes <= caches.sopL2.lineBytes, "SOP L1 line must not be longer than the SOP L2 line")
  for ((name, g, l2) <- Seq(("TS L2", caches.tsL2, uncore.tsL2), ("SOP L2", caches.sopL2, uncore.sopL2)))
    require(L2Structure.splits(g, l2.banks),
      s"$name of ${g.describe} cannot be split into ${l2.banks} banks: each needs two lines and a set of its own")
  require(queues.registerQueueDepth >= indices.nodeBits + 4,
    s"Register queue depth ${queues.registerQueueDepth} must exceed the tree-depth reserve: at least ${indices.nodeBits + 4} for ${indices.nodeBits}-bit node indices")
  require(queues.rsEntries % counts.soaPerSom == 0 && queues.rsEntries / counts.soaPerSom >= SoGroup.Size,
    s"reservation-station entries ${queues.rsEntries} must split evenly into at least ${SoGroup.Size} per SOA (${counts.soaPerSom} SOAs per SOM)")

  /** The frame accumulation's definition for this configuration (mapm.numerics.FrameAccum). */
  def frameAccum: mapm.numerics.FrameAccum = {
    val d = mapm.numerics.FrameAccum.default(numbers.format)
    d.copy(accBits = if (coproc.accBits == 0) d.accBits else coproc.accBits, countBits = coproc.countBits)
  }
  /** Banks of the frame accumulator. */
  def frameBanks: Int =
    if (coproc.banks != 0) coproc.banks
    else math.min(1 << coproc.tileLog2, math.max(1, Integer.highestOneBit(counts.som * counts.soaPerSom)))
  require(frameAccum.limitBits >= numbers.format.manWidth + 2,
    s"frame sums of ${frameAccum.accBits} bits with ${coproc.countBits}-bit counts leave too few bits for a ${numbers.format.manWidth + 1}-bit significand")

  /** Reservation-station entries of one SOA's lane. */
  def rsPerSoa: Int = queues.rsEntries / counts.soaPerSom
  /** Geometry of one SOP L1 bank: a SOM's SOP L1 is split into one bank per SOA (photon record i
    * in bank i mod soaPerSom), each of size sopL1 / (soaPerSom rounded up to a power of two). */
  def sopL1Bank: CacheParams = {
    val banks = Integer.highestOneBit(counts.soaPerSom) match { case b if b == counts.soaPerSom => b; case b => 2 * b }
    val g = caches.sopL1
    val size = math.max(g.sizeBytes / banks, g.lineBytes * g.ways * 2)
    g.copy(sizeBytes = size)
  }

  /** Geometry of one TS L2 bank ([[UncoreParams.tsL2]]; the whole TS L2 when shared). */
  def tsL2Bank: CacheParams = MapmParams.l2Bank(caches.tsL2, uncore.tsL2)
  /** Geometry of one SOP L2 bank ([[UncoreParams.sopL2]]; the whole SOP L2 when shared). */
  def sopL2Bank: CacheParams = MapmParams.l2Bank(caches.sopL2, uncore.sopL2)

  /** Short name used in module and file names, e.g. `t16s16a2_e8m23_g3`, with `_wide` where the
    * wide layout gives the format larger slots than the packed one, the FPU logic per stage
    * (e.g. `_fw1p5`) where it is not the default, `_conv` for the conventional arithmetic,
    * `_timing` for the SOAs' timing model, `_nocg` for SOAs without clock gating, `_nsg` for SOAs without stage gating and `_b8` for
    * an SOP L2 of 8 banks. */
  def name: String = {
    val wide = if (slotBytes != SlotLayout.Packed.slotBytes(numbers.format)) "_wide" else ""
    val w = numbers.fpuStageWeight
    val depth = if (w != NumberParams.DefaultFpuStageWeight) "_fw" + f"$w%.2f".stripSuffix("0").stripSuffix("0").stripSuffix(".").replace('.', 'p') else ""
    val conv = if (numbers.arith == Arith.Conventional) "_conv" else ""
    val timing = if (sim.fidelity == Fidelity.Timing) "_timing" else ""
    val gate = (if (clocking.soaClockGate) "" else "_nocg") + (if (clocking.soaStageGate) "" else "_nsg")
    val bus = if (uncore.soBus == SoBus.Serial) "" else s"_${uncore.soBus.name}"
    def banks(l2: L2Structure, tag: String) = l2 match { case L2Structure.Shared => ""; case L2Structure.Banked(n) => s"_$tag$n" }
    s"t${counts.tsm}s${counts.som}a${counts.soaPerSom}_${numbers.format.name}_g${numbers.guardDigits}$wide$depth$conv$timing$gate${banks(uncore.sopL2, "b")}${banks(uncore.tsL2, "tb")}$bus"
  }
}

/** The presets, each a `.copy` of the one above it: the dissertation's MAPM, Table 4.8's
  * configurations of it, the small MAPM that the tests share, and the default: the dissertation's
  * MAPM with the scalable memory hierarchy ([[Hierarchy.Scalable]]). */
object MapmParams {
  /** One bank of an L2 of geometry `g` built as `l2`: 1/banks of the capacity, fully associative
    * when `g` is, else the same ways over 1/banks of the sets (the whole L2 when shared). */
  def l2Bank(g: CacheParams, l2: L2Structure): CacheParams =
    g.copy(sizeBytes = g.sizeBytes / l2.banks, ways = if (g.fullyAssociative) g.lines / l2.banks else g.ways)

  /** The dissertation's MAPM (sections 3.2 and 4.1): 16 TSMs, 16 SOMs of 2 SOAs, fp32 with the
    * online arithmetic, Table 4.2's caches, 8 reservation-station entries per SOA. Every field's
    * default is this preset's. */
  val dissertation: MapmParams = MapmParams()

  /** A configuration of Table 4.8 (TSMs/SOMs/SOAs per SOM): the dissertation's MAPM with these
    * counts and 8 reservation-station entries per SOA. */
  def table48(tsm: Int, som: Int, soa: Int): MapmParams =
    dissertation.copy(counts = ModuleCounts(tsm, som, soa), queues = dissertation.queues.copy(rsEntries = 8 * soa))

  /** The 24 configurations of Table 4.8, by label (e.g. "16/16/2"). */
  val table48Configs: Seq[(Int, Int, Int)] = Seq(
    (1, 1, 2), (1, 1, 3), (2, 1, 2), (2, 1, 3), (2, 2, 2), (2, 2, 3), (2, 3, 2), (2, 3, 3),
    (4, 2, 2), (4, 2, 3), (4, 4, 2), (4, 4, 3), (4, 6, 2), (4, 6, 3), (8, 4, 2), (8, 4, 3),
    (8, 8, 2), (8, 8, 3), (8, 12, 2), (8, 12, 3), (16, 8, 2), (16, 8, 3), (16, 16, 2), (16, 16, 3))

  /** Table 4.8's configurations by label. */
  val presets: Map[String, MapmParams] =
    table48Configs.map { case (t, s, a) => s"$t/$s/$a" -> table48(t, s, a) }.toMap

  /** The default configuration, every command's: the dissertation's 16/16/2 at fp32 (its best
    * throughput per area) with the scalable memory hierarchy. */
  val default: MapmParams = Hierarchy.Scalable(dissertation)

  /** The small MAPM the tests share: one TSM and one SOM with one SOA (1/1/1), the rest the
    * dissertation's, with the scalable hierarchy (for 1/1/1: a shared SOP L2 and a 4-way SOQ); it
    * elaborates and simulates in seconds, and it is what `--tsm 1 --som 1 --soa 1` gives. */
  val small: MapmParams = Hierarchy.Scalable(table48(1, 1, 1))
}
