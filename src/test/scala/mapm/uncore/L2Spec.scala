package mapm.uncore

import chisel3._
import chiseltest._
import mapm.Slow
import mapm.memory.{CacheConfig, DramModel, DramTiming, MemArbiter, MemImage, MemPortParams, MemSim, PortClient}
import mapm.params._
import mapm.testutil.Sim
import org.scalatest.funsuite.AnyFunSuite
import scala.util.Random

/** The L2 (the TS L2's and the SOP L2's module) in both structures, between PortClients standing
  * in for the L1s (here shaped as SOP L1 banks) and one
  * behavioural DRAM per bank (random latency, refusals and response order), under random client
  * stalls: every read returns its bytes (none lost, none duplicated); each bank fetches exactly the
  * lines of its own (line address mod banks), each once while the working set fits; hits and misses
  * equal those of that reference; the conflict counter is exact on hand-built patterns. */
@Slow
class L2Spec extends AnyFunSuite with Sim {
  private val memSize = 1 << 14
  private val lineBytes = 64
  /** An SOP L1 bank's miss port: single-beat reads of one 32-byte line, 2-bit ids. */
  private val up = MemPortParams(32, 32, 2)

  /** An L2 of `l2Bytes` (fully associative, 64-byte lines) under `clients` L1s, built as `l2`. */
  private def l2(clients: Int, l2: L2Structure, l2Bytes: Int): L2 = {
    val bank = MapmParams.l2Bank(CacheParams(l2Bytes, lineBytes, l2Bytes / lineBytes), l2)
    new L2("sop", clients, up, CacheConfig.below(MemArbiter.downParams(Seq.fill(clients)(up)), bank).copy(interleave = l2.banks), l2)
  }

  /** Runs `reads` random reads per client over `span` bytes; returns each bank's DRAM requests
    * and the reads issued. */
  private def run(c: L2, seed: Long, reads: Int, span: Int): (Seq[Seq[Long]], Seq[IndexedSeq[Long]]) = {
    c.clock.setTimeout(0)
    val rnd = new Random(seed)
    val mem = new MemImage(memSize, seed)
    c.io.l1.foreach(_.req.valid.poke(false.B))
    c.io.mem.foreach(_.resp.valid.poke(false.B))
    MemSim.reset(c.clock, c.reset)
    val streams = c.io.l1.indices.map(_ => IndexedSeq.fill(reads)(rnd.nextInt(span / 32).toLong * 32))
    val clients = streams.zipWithIndex.map { case (s, i) =>
      new PortClient(c.io.l1(i), mem, s, 0.3 + 0.7 * rnd.nextDouble(), 0.3 + 0.7 * rnd.nextDouble(), rnd, s"L1 bank $i")
    }
    val drams = c.io.mem.map(m => new DramModel(m, mem, DramTiming(Seq(0, 20, 150)(rnd.nextInt(3)), 0.3 + 0.7 * rnd.nextDouble(),
      0.3 + 0.7 * rnd.nextDouble()), rnd))
    MemSim.run(c.clock, clients.map(k => () => k.drive()) ++ drams.map(d => () => d.drive()),
      clients.map(k => () => k.observe()) ++ drams.map(d => () => d.observe()), clients.forall(_.done))
    assert(clients.map(_.responses).sum == streams.map(_.size).sum, "every read answered once")
    (drams.map(_.requests.toSeq), streams)
  }

  // Above eight L1s the banked network groups them (L2Group): 11 makes groups of 8 and 3, 17 of 8, 8 and 1.
  for ((clients, structure) <- Seq((4, L2Structure.Shared), (4, L2Structure.Banked(2)), (3, L2Structure.Banked(4)), (3, L2Structure.Banked(8)),
      (11, L2Structure.Banked(4)), (17, L2Structure.Banked(2)))) {
    test(s"$clients L1s over an L2 ${structure.name}: every read right; each bank fetches its own lines once; hits and misses exact") {
      simulate(l2(clients, structure, 8192)) { c =>
        for (seed <- 0 until 6) {
          // The working set (4 KiB) fits every bank: each line is fetched once, by its own bank.
          val (fetched, streams) = run(c, seed, 250, 4096)
          val lines = streams.flatten.map(_ / lineBytes).distinct
          for ((f, b) <- fetched.zipWithIndex) {
            val mine = lines.filter(_ % structure.banks == b).map(_ * lineBytes)
            assert(f.sorted == mine.sorted, s"seed $seed: bank $b fetched ${f.size} lines, its own are ${mine.size}")
          }
          val total = streams.map(_.size).sum.toLong
          val (hits, misses) = (c.io.counters.hits.peek().litValue, c.io.counters.misses.peek().litValue)
          assert(misses == lines.size && hits + misses == total, s"seed $seed: $hits hits, $misses misses of $total reads")
          c.reset.poke(true.B); c.clock.step(); c.reset.poke(false.B)
        }
      }
    }
  }

  test("banked under eviction (a working set 4 times the SOP L2): every read right, every fetch by the bank its line names") {
    simulate(l2(4, L2Structure.Banked(4), 2048)) { c =>
      for (seed <- 0 until 4) {
        val (fetched, _) = run(c, 100 + seed, 400, 8192)
        for ((f, b) <- fetched.zipWithIndex) assert(f.forall(a => (a / lineBytes) % 4 == b), s"seed $seed: bank $b fetched another bank's line")
        c.reset.poke(true.B); c.clock.step(); c.reset.poke(false.B)
      }
    }
  }

  test("conflict counter: k reads of one bank offered at once wait 0 + 1 + ... + (k - 1) cycles; reads of different banks none") {
    simulate(l2(3, L2Structure.Banked(2), 8192)) { c =>
      c.clock.setTimeout(0)
      c.io.l1.foreach(_.req.valid.poke(false.B))
      c.io.l1.foreach(_.resp.ready.poke(true.B))
      c.io.mem.foreach { m => m.req.ready.poke(false.B); m.resp.valid.poke(false.B) }
      MemSim.reset(c.clock, c.reset)
      c.clock.step(200) // the banks clear their tags
      var before = BigInt(0)
      for ((addrs, want) <- Seq(Seq(0L, 128L, 256L) -> 3, Seq(64L, 192L) -> 1, Seq(0L, 64L) -> 0, Seq(512L, 576L, 640L) -> 1)) {
        for ((a, i) <- addrs.zipWithIndex) {
          c.io.l1(i).req.valid.poke(true.B)
          c.io.l1(i).req.bits.addr.poke(a.U)
          c.io.l1(i).req.bits.id.poke(0.U)
        }
        c.clock.step() // taken into the input registers
        addrs.indices.foreach(i => c.io.l1(i).req.valid.poke(false.B))
        c.clock.step(10)
        val now = c.io.counters.conflicts.peek().litValue
        assert(now - before == want, s"reads at ${addrs.mkString(", ")}: ${now - before} conflict cycles, expected $want")
        before = now
        c.reset.poke(true.B); c.clock.step(); c.reset.poke(false.B); c.clock.step(200)
        before = c.io.counters.conflicts.peek().litValue
      }
    }
  }
}
