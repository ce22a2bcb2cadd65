package mapm.memory

import mapm.Slow
import chisel3._
import chisel3.util._
import chiseltest._
import mapm.testutil.Sim
import mapm.params.CacheParams
import org.scalatest.funsuite.AnyFunSuite
import scala.util.Random

/** Test top: `n` L1 caches over one L2, the way the TS and SOP blocks use them. With one L1 its
  * lower port is wired straight to the L2's upper port; with more they share it through a
  * [[MemArbiter]]. The requests the L2 takes are exposed so the test can replay them into the
  * L2's reference model. */
class CacheChain(val l1: CacheConfig, val n: Int, l2Geometry: CacheParams) extends Module {
  private val l2Up = if (n == 1) l1.down else l1.down.widenId(log2Ceil(n))
  val l2: CacheConfig = CacheConfig.below(l2Up, l2Geometry, downBytes = 16, mshrs = 4, targets = 8, maxWays = 4)
  val io = IO(new Bundle {
    val up = Vec(n, Flipped(new MemPort(l1.up)))
    val down = new MemPort(l2.down)
    val l1Counters = Output(Vec(n, new CacheCounters(l1.counterBits)))
    val l2Counters = Output(new CacheCounters(l2.counterBits))
    /** The request the L2 takes this cycle. */
    val l2Req = Output(Valid(new MemReq(l2.up)))
  })
  val l1s = Seq.fill(n)(Module(new ReadOnlyCache(l1)))
  val l2Cache = Module(new ReadOnlyCache(l2))
  if (n == 1) l2Cache.io.up <> l1s.head.io.down
  else {
    val arb = Module(new MemArbiter(l1.down, n, maxOutstanding = 6))
    arb.io.up.zip(l1s).foreach { case (a, c) => a <> c.io.down }
    l2Cache.io.up <> arb.io.down
  }
  io.down <> l2Cache.io.down
  io.up.zip(l1s).foreach { case (u, c) => u <> c.io.up }
  io.l1Counters := VecInit(l1s.map(_.io.counters))
  io.l2Counters := l2Cache.io.counters
  io.l2Req.valid := l2Cache.io.up.req.fire
  io.l2Req.bits := l2Cache.io.up.req.bits
}

/** L1 + L2 chains against the behavioural DRAM: every read correct, and the counts of both levels
  * equal their reference models (the L1's over its client stream, the L2's over the requests it
  * took, which must be the L1s' misses with each L1's order kept). */
@Slow
class CacheChainSpec extends AnyFunSuite with Sim {
  private val memSize = 1 << 14
  private val l1 = CacheConfig(CacheParams(512, 32, 2), 8, 3, 16, downBytes = 32, mshrs = 2, targets = 4)
  // Fully associative, 32 lines: built 4-way with the hashed index, as the Table 4.2 L2s are.
  private val l2Geometry = CacheParams(2048, 64, 32)

  private def run(c: CacheChain, seeds: Int): Unit = {
    c.clock.setTimeout(0)
    var reads = 0L
    for (seed <- 0 until seeds) {
      val rnd = new Random(seed)
      val mem = new MemImage(memSize, seed)
      c.io.up.foreach(_.req.valid.poke(false.B))
      c.io.down.resp.valid.poke(false.B)
      MemSim.reset(c.clock, c.reset)
      val streams = Seq.tabulate(c.n) { i =>
        if ((seed + i) % 2 == 0) AddressStreams.treeWalks(600, memSize, 8, rnd)
        else AddressStreams.local(600, memSize, 8, rnd)
      }
      val clients = streams.zipWithIndex.map { case (s, i) =>
        new PortClient(c.io.up(i), mem, s, 0.3 + 0.7 * rnd.nextDouble(), 0.3 + 0.7 * rnd.nextDouble(), rnd, s"L1 $i")
      }
      val timing = DramTiming(Seq(2, 30, 300)(seed % 3), 0.3 + 0.7 * rnd.nextDouble(), 0.3 + 0.7 * rnd.nextDouble())
      val dram = new DramModel(c.io.down, mem, timing, rnd)
      val l2Seen = scala.collection.mutable.ArrayBuffer[(Int, Long)]() // (source L1, line address)
      val watchL2 = () => {
        if (c.io.l2Req.valid.peek().litToBoolean)
          l2Seen += (((c.io.l2Req.bits.id.peek().litValue >> c.l1.down.idBits).toInt,
            c.io.l2Req.bits.addr.peek().litValue.toLong))
        false
      }
      MemSim.run(c.clock, clients.map(k => () => k.drive()) :+ (() => dram.drive()),
        clients.map(k => () => k.observe()) ++ Seq(() => dram.observe(), watchL2), clients.forall(_.done))
      val what = s"seed $seed, $timing"
      val l1Refs = streams.map { s => val r = RefCache(c.l1); s.foreach(r.access); r }
      for ((r, i) <- l1Refs.zipWithIndex) {
        assert(c.io.l1Counters(i).hits.peek().litValue == r.hits, s"L1 $i hits, $what")
        assert(c.io.l1Counters(i).misses.peek().litValue == r.misses, s"L1 $i misses, $what")
      }
      // The L2 took each L1's misses in that L1's order (interleaved among the L1s).
      for ((r, i) <- l1Refs.zipWithIndex)
        assert(l2Seen.filter(_._1 == i).map(_._2) == r.fetched, s"L2 requests from L1 $i are its misses, $what")
      assert(l2Seen.size == l1Refs.map(_.fetched.size).sum, what)
      val l2Ref = RefCache(c.l2)
      l2Seen.foreach { case (_, a) => l2Ref.access(a) }
      assert(c.io.l2Counters.hits.peek().litValue == l2Ref.hits, s"L2 hits, $what")
      assert(c.io.l2Counters.misses.peek().litValue == l2Ref.misses, s"L2 misses, $what")
      assert(c.io.l2Counters.bytesFetched.peek().litValue == l2Ref.misses * c.l2.lineBytes, s"L2 bytes, $what")
      assert(dram.requests == l2Ref.fetched, s"DRAM requests are the L2 misses in order, $what")
      reads += streams.map(_.size).sum
    }
    info(s"$seeds seeds, $reads reads checked")
  }

  test("an L1 wired straight into an L2 (the L2's word is the L1's line): 24 seeds") {
    simulate(new CacheChain(l1, 1, l2Geometry)) { c => run(c, 24) }
  }

  test("latency through the chain: L1 miss hitting the L2 8 cycles, missing both 10 + L2 beats") {
    simulate(new CacheChain(l1, 1, l2Geometry)) { c =>
      c.clock.setTimeout(0)
      val mem = new MemImage(memSize, 3)
      val rnd = new Random(3)
      c.io.up(0).req.valid.poke(false.B)
      c.io.down.resp.valid.poke(false.B)
      MemSim.reset(c.clock, c.reset)
      val dram = new DramModel(c.io.down, mem, DramTiming(0, 1.0, 1.0), rnd)
      // One read at a time: 128 misses both levels, 160 (the other half of its L2 line) only the L1.
      for ((addr, want) <- Seq(128L -> (10 + c.l2.beatsPerLine), 160L -> 8)) {
        val client = new PortClient(c.io.up(0), mem, IndexedSeq(addr), 1.0, 1.0, rnd)
        MemSim.run(c.clock, Seq(() => client.drive(), () => dram.drive()), Seq(() => client.observe(), () => dram.observe()), client.done)
        assert(client.latencies == Seq(want.toLong), s"read at $addr")
      }
    }
  }

  test("two L1s sharing an L2 through the round-robin arbiter: 24 seeds") {
    simulate(new CacheChain(l1, 2, l2Geometry)) { c => run(c, 24) }
  }
}
