package mapm.uncore

import chisel3._
import chiseltest._
import mapm.Slow
import mapm.memory.{DramModel, DramTiming, MemImage, MemPortParams, MemSim, PortClient}
import mapm.params._
import mapm.testutil.Sim
import org.scalatest.funsuite.AnyFunSuite
import scala.util.Random

/** The SOP L2 in both structures, between PortClients standing in for the SOP L1 banks and one
  * behavioural DRAM per bank (random latency, refusals and response order), under random client
  * stalls: every read returns its bytes (none lost, none duplicated); each bank fetches exactly the
  * lines of its own (line address mod banks), each once while the working set fits; hits and misses
  * equal those of that reference; the conflict counter is exact on hand-built patterns. */
@Slow
class SopL2Spec extends AnyFunSuite with Sim {
  private val memSize = 1 << 14
  private val lineBytes = 64
  /** An SOP L1 bank's miss port: single-beat reads of one 32-byte line, 2-bit ids. */
  private val up = MemPortParams(32, 32, 2)

  private def params(som: Int, soa: Int, l2: L2Structure, l2Bytes: Int): MapmParams = {
    val s = MapmParams.small
    s.copy(counts = ModuleCounts(1, som, soa), queues = s.queues.copy(rsEntries = 8 * soa),
      caches = s.caches.copy(sopL2 = CacheParams(l2Bytes, lineBytes, l2Bytes / lineBytes)), uncore = UncoreParams(l2))
  }

  /** Runs `reads` random reads per client over `span` bytes; returns each bank's DRAM requests
    * and the reads issued. */
  private def run(c: SopL2, seed: Long, reads: Int, span: Int): (Seq[Seq[Long]], Seq[IndexedSeq[Long]]) = {
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

  for ((som, soa, l2) <- Seq((2, 2, L2Structure.Shared), (2, 2, L2Structure.Banked(2)), (3, 1, L2Structure.Banked(4)),
                             (1, 3, L2Structure.Banked(8)))) {
    test(s"$som SOMs x $soa SOAs over an SOP L2 ${l2.name}: every read right; each bank fetches its own lines once; hits and misses exact") {
      val p = params(som, soa, l2, 8192)
      simulate(new SopL2(p, up)) { c =>
        for (seed <- 0 until 6) {
          // The working set (4 KiB) fits every bank: each line is fetched once, by its own bank.
          val (fetched, streams) = run(c, seed, 250, 4096)
          val lines = streams.flatten.map(_ / lineBytes).distinct
          for ((f, b) <- fetched.zipWithIndex) {
            val mine = lines.filter(_ % l2.banks == b).map(_ * lineBytes)
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
    val p = params(2, 2, L2Structure.Banked(4), 2048)
    simulate(new SopL2(p, up)) { c =>
      for (seed <- 0 until 4) {
        val (fetched, _) = run(c, 100 + seed, 400, 8192)
        for ((f, b) <- fetched.zipWithIndex) assert(f.forall(a => (a / lineBytes) % 4 == b), s"seed $seed: bank $b fetched another bank's line")
        c.reset.poke(true.B); c.clock.step(); c.reset.poke(false.B)
      }
    }
  }

  test("conflict counter: k reads of one bank offered at once wait 0 + 1 + ... + (k - 1) cycles; reads of different banks none") {
    val p = params(3, 1, L2Structure.Banked(2), 8192)
    simulate(new SopL2(p, up)) { c =>
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
