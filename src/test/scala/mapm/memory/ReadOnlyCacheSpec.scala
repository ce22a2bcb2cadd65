package mapm.memory

import mapm.Slow
import chisel3._
import chiseltest._
import mapm.testutil.Sim
import mapm.params.{CacheParams, CachesParams}
import org.scalatest.funsuite.AnyFunSuite
import scala.util.Random

/** [[ReadOnlyCache]] against a behavioural DRAM (random latency 0..300 cycles, reordering, gaps) and
  * a randomly stalling client: every read must return the word of the memory image under its id,
  * none lost or duplicated; hit and miss counts, fetched bytes and the order of line fetches must
  * equal those of the independent reference model [[RefCache]]. Many seeds per simulation (reset
  * between seeds). */
@Slow
class ReadOnlyCacheSpec extends AnyFunSuite with Sim {
  private val memSize = 1 << 16

  /** A stream of `n` reads for `seed`: uniform, tree walks, local or launch order. */
  type Stream = (Int, Int, Random) => IndexedSeq[Long]

  /** Totals over the runs of one test: reads, cycles, hits, most line fetches in flight at once. */
  private final class Totals { var reads = 0L; var cycles = 0L; var hits = 0L; var inFlight = 0 }
  private var totals = new Totals

  /** One seeded run on a freshly reset cache; returns the client (for its latencies). */
  private def runSeed(c: ReadOnlyCache, seed: Int, addrs: IndexedSeq[Long], timing: DramTiming,
                      reqValid: Double, respReady: Double): PortClient = {
    val cfg = c.cfg
    val rnd = new Random(seed * 7919L + 1)
    val mem = new MemImage(memSize, seed)
    c.io.up.req.valid.poke(false.B)
    c.io.down.resp.valid.poke(false.B)
    MemSim.reset(c.clock, c.reset)
    val client = new PortClient(c.io.up, mem, addrs, reqValid, respReady, rnd)
    val dram = new DramModel(c.io.down, mem, timing, rnd)
    val cycles = MemSim.run(c.clock, Seq(() => client.drive(), () => dram.drive()),
      Seq(() => client.observe(), () => dram.observe()), client.done)
    val ref = RefCache(cfg)
    addrs.foreach(ref.access)
    val what = s"seed $seed, ${addrs.size} reads, $timing"
    assert(client.responses == addrs.size, what)
    assert(c.io.counters.hits.peek().litValue == ref.hits, s"hits, $what")
    assert(c.io.counters.misses.peek().litValue == ref.misses, s"misses, $what")
    assert(c.io.counters.bytesFetched.peek().litValue == ref.misses * cfg.lineBytes, s"bytes, $what")
    assert(dram.requests == ref.fetched, s"line fetch order, $what")
    assert(!c.io.protocolError.peek().litToBoolean, what)
    totals.reads += addrs.size; totals.cycles += cycles; totals.hits += ref.hits
    totals.inFlight = totals.inFlight max dram.maxOutstanding
    client
  }

  /** Random runs: `seeds` seeds cycling through `streams` and three latency ranges (0..2, 0..30,
    * 0..300), with random handshake probabilities. */
  private def randomRuns(c: ReadOnlyCache, seeds: Int, reads: Int, span: Int, streams: Seq[Stream]): Unit = {
    c.clock.setTimeout(0)
    totals = new Totals
    for (seed <- 0 until seeds) {
      val rnd = new Random(seed)
      val timing = DramTiming(Seq(2, 30, 300)(seed % 3), 0.3 + 0.7 * rnd.nextDouble(), 0.3 + 0.7 * rnd.nextDouble())
      val n = if (timing.maxLatency > 30) reads / 2 else reads
      val addrs = streams(seed % streams.size)(n, span, rnd)
      runSeed(c, seed, addrs, timing, 0.2 + 0.8 * rnd.nextDouble(), 0.2 + 0.8 * rnd.nextDouble())
    }
    info(f"$seeds seeds: ${totals.reads} reads checked in ${totals.cycles} cycles, hit rate " +
      f"${100.0 * totals.hits / totals.reads}%.1f%%, up to ${totals.inFlight} line fetches in flight")
  }

  private def streams(word: Int): Seq[Stream] = Seq(
    (n, span, r) => AddressStreams.uniform(n, span, word, r),
    (n, span, r) => AddressStreams.treeWalks(n, span, word, r),
    (n, span, r) => AddressStreams.local(n, span, word, r))

  private val twoWay = CacheConfig(CacheParams(1024, 32, 2), wordBytes = 8, idBits = 4, addressBits = 16,
    downBytes = 16, mshrs = 4, targets = 8)

  test("2-way 1 KiB, 8-byte words, 2-beat refills, 4 MSHRs: 60 seeds") {
    simulate(new ReadOnlyCache(twoWay)) { c => randomRuns(c, 60, 1200, 8192, streams(8)) }
  }

  test("blocking (1 MSHR, 1 waiting access) 4-way 512 B, 4-byte words, 4-beat refills: 30 seeds") {
    val cfg = CacheConfig(CacheParams(512, 16, 4), 4, 2, 16, 4, mshrs = 1, targets = 1)
    simulate(new ReadOnlyCache(cfg)) { c => randomRuns(c, 30, 800, 4096, streams(4)) }
  }

  test("fully associative 8 lines, one word per line: 30 seeds") {
    val cfg = CacheConfig(CacheParams(256, 32, 8), 32, 3, 16, 8, mshrs = 2, targets = 3)
    assert(cfg.hw.fullyAssociative)
    simulate(new ReadOnlyCache(cfg)) { c => randomRuns(c, 30, 800, 2048, streams(32)) }
  }

  test("fully associative 64 lines built 4-way with the hashed set index (as the L2s): 30 seeds") {
    val cfg = CacheConfig(CacheParams(2048, 32, 64), 8, 4, 16, 16, mshrs = 4, targets = 6, maxWays = 4)
    assert(cfg.hashed && cfg.ways == 4 && cfg.sets == 16)
    simulate(new ReadOnlyCache(cfg)) { c => randomRuns(c, 30, 1200, 16384, streams(8)) }
  }

  test("direct mapped (SOQ-like) on launch-ordered records: only compulsory misses, as a FIFO; 30 seeds") {
    val cfg = CacheConfig(CacheParams(1024, 32, 1), 32, 5, 16, 16, mshrs = 4, targets = 8)
    simulate(new ReadOnlyCache(cfg)) { c =>
      c.clock.setTimeout(0)
      for (seed <- 0 until 30) {
        val rnd = new Random(seed)
        val window = 1 + rnd.nextInt(cfg.hw.lines) // never more records live than lines
        val timing = DramTiming(Seq(2, 30, 300)(seed % 3), 0.5, 0.5)
        val used = AddressStreams.launchOrder(if (timing.maxLatency > 30) 500 else 1000, memSize, 32, window,
          1 + rnd.nextInt(6), rnd)
        runSeed(c, seed, used, timing, 0.8, 0.6)
        val fifo = new RefLruCache(1, cfg.hw.lines, cfg.lineBytes, lru = false)
        used.foreach(fifo.access)
        assert(c.io.counters.misses.peek().litValue == used.distinct.size, s"seed $seed: compulsory misses only")
        assert(fifo.misses == used.distinct.size, s"seed $seed: the FIFO cache agrees")
      }
    }
  }

  test("Table 4.2 TS L1 geometry (16 KiB, 32 B lines, 2-way, 256 sets), tree walks over 64 KiB: 6 seeds") {
    val cfg = CacheConfig(CachesParams().tsL1, 8, 4, 32, downBytes = 32, mshrs = 4, targets = 8)
    simulate(new ReadOnlyCache(cfg)) { c =>
      randomRuns(c, 6, 3000, memSize, Seq((n, span, r) => AddressStreams.treeWalks(n, span, 8, r)))
    }
  }

  test("hit latency 3 cycles at one hit per cycle; miss latency 5 + beats cycles at zero memory latency") {
    simulate(new ReadOnlyCache(twoWay)) { c =>
      c.clock.setTimeout(0)
      val instant = DramTiming(0, 1.0, 1.0)
      val miss = runSeed(c, 1, IndexedSeq(64L), instant, 1.0, 1.0)
      assert(miss.latencies == Seq(5L + twoWay.beatsPerLine))
      // Four lines fetched, then 200 hits on them back to back.
      val lines = IndexedSeq(0L, 32L, 64L, 96L)
      val hits = IndexedSeq.tabulate(200)(i => lines(i % 4) + 8 * ((i / 4) % 4))
      val mem = new MemImage(memSize, 2)
      c.io.down.resp.valid.poke(false.B)
      MemSim.reset(c.clock, c.reset)
      val rnd = new Random(2)
      val warm = new PortClient(c.io.up, mem, lines, 1.0, 1.0, rnd)
      val dram = new DramModel(c.io.down, mem, instant, rnd)
      MemSim.run(c.clock, Seq(() => warm.drive(), () => dram.drive()), Seq(() => warm.observe(), () => dram.observe()), warm.done)
      val client = new PortClient(c.io.up, mem, hits, 1.0, 1.0, rnd)
      val cycles = MemSim.run(c.clock, Seq(() => client.drive(), () => dram.drive()),
        Seq(() => client.observe(), () => dram.observe()), client.done)
      assert(client.latencies.forall(_ == 3), client.latencies.distinct)
      assert(cycles == 200 + 3, s"200 hits took $cycles cycles")
      assert(c.io.counters.hits.peek().litValue == 200 && c.io.counters.misses.peek().litValue == 4)
    }
  }

  test("a misaligned read sets the sticky protocol-error flag and is served from its word") {
    simulate(new ReadOnlyCache(twoWay)) { c =>
      c.clock.setTimeout(0)
      c.io.up.req.valid.poke(false.B)
      c.io.down.resp.valid.poke(false.B)
      MemSim.reset(c.clock, c.reset)
      val rnd = new Random(5)
      val mem = new MemImage(memSize, 5)
      val client = new PortClient(c.io.up, mem, IndexedSeq(16L, 40L + 3, 48L), 1.0, 1.0, rnd)
      val dram = new DramModel(c.io.down, mem, DramTiming(5, 1.0, 1.0), rnd)
      assert(!c.io.protocolError.peek().litToBoolean)
      MemSim.run(c.clock, Seq(() => client.drive(), () => dram.drive()), Seq(() => client.observe(), () => dram.observe()), client.done)
      assert(c.io.protocolError.peek().litToBoolean)
    }
  }
}
