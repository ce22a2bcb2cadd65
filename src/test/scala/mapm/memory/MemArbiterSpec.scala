package mapm.memory

import mapm.Slow
import chisel3._
import chiseltest._
import mapm.testutil.Sim
import org.scalatest.funsuite.AnyFunSuite
import scala.collection.mutable
import scala.util.Random

/** A requester of multi-beat reads on one arbiter port: random aligned bursts under unique ids,
  * each response beat checked (routed to the right port, right id, beats in order with the right
  * data, `last` on the final one). Counts how many grants other ports got while it waited. */
final class BurstClient(port: MemPort, mem: MemImage, count: Int, reqValid: Double, respReady: Double,
                        rnd: Random, val index: Int) {
  private val p = port.p
  private val outstanding = mutable.Map[BigInt, (Long, Int, Int)]() // id -> (addr, beats, next beat)
  private var offered: Option[(BigInt, Long, Int)] = None
  private var takeResp = false
  private var sent = 0
  var othersWhileWaiting = 0
  var worstWait = 0
  var beats = 0

  def done: Boolean = sent == count && outstanding.isEmpty && offered.isEmpty
  def waiting: Boolean = offered.isDefined

  def drive(): Unit = {
    if (offered.isEmpty && sent < count && rnd.nextDouble() < reqValid) {
      val free = (0 until (1 << p.idBits)).map(BigInt(_)).filterNot(outstanding.contains)
      if (free.nonEmpty) {
        val b = 1 << rnd.nextInt(java.lang.Integer.numberOfTrailingZeros(p.maxBeats) + 1)
        val addr = rnd.nextInt(mem.size / (b * p.dataBytes)).toLong * b * p.dataBytes
        offered = Some((free(rnd.nextInt(free.size)), addr, b))
      }
    }
    port.req.valid.poke(offered.isDefined.B)
    offered.foreach { case (id, addr, b) =>
      port.req.bits.addr.poke(addr.U)
      port.req.bits.id.poke(id.U)
      port.req.bits.len.poke((b - 1).U)
    }
    takeResp = rnd.nextDouble() < respReady
    port.resp.ready.poke(takeResp.B)
  }

  def observe(): Boolean = {
    var progress = false
    offered.foreach { case (id, addr, b) =>
      if (port.req.ready.peek().litToBoolean) {
        outstanding(id) = (addr, b, 0)
        sent += 1
        offered = None
        worstWait = worstWait max othersWhileWaiting
        othersWhileWaiting = 0
        progress = true
      }
    }
    if (takeResp && port.resp.valid.peek().litToBoolean) {
      val id = port.resp.bits.id.peek().litValue
      val (addr, b, k) = outstanding.getOrElse(id, throw new AssertionError(s"port $index: beat for id $id, not outstanding here"))
      assert(port.resp.bits.data.peek().litValue == mem.read(addr + k * p.dataBytes, p.dataBytes), s"port $index id $id beat $k")
      assert(port.resp.bits.last.peek().litToBoolean == (k == b - 1), s"port $index id $id beat $k of $b: last")
      if (k == b - 1) outstanding -= id else outstanding(id) = (addr, b, k + 1)
      beats += 1
      progress = true
    }
    progress
  }
}

/** [[MemArbiter]]: responses route back to the right port and id through a reordering DRAM, the
  * in-flight limit holds and is reached, and the grant is round-robin: a waiting port never sees
  * more than n-1 grants to the others before its own. */
@Slow
class MemArbiterSpec extends AnyFunSuite with Sim {
  private val up = MemPortParams(addressBits = 16, dataBytes = 8, idBits = 2, maxBeats = 4)

  /** One seed's run of `count` bursts from every port of `ups` through an arbiter to a reordering
    * DRAM: resets, drives the clients and the DRAM until every client is done, counting for each
    * waiting port the grants to others (by the source bits above `idBits`). Odd seeds keep every
    * port asking. Returns the clients, the DRAM and whether the seed was a busy one. */
  private def runSeed(clock: Clock, reset: Reset, ups: Seq[MemPort], down: MemPort, idBits: Int, count: Int, seed: Int,
                      rnd: Random): (Seq[BurstClient], DramModel, DramTiming, Boolean) = {
    val mem = new MemImage(1 << 12, seed)
    ups.foreach(_.req.valid.poke(false.B))
    down.resp.valid.poke(false.B)
    MemSim.reset(clock, reset)
    val busy = seed % 2 == 1
    val clients = ups.indices.map(i => new BurstClient(ups(i), mem, count,
      if (busy) 1.0 else 0.2 + 0.8 * rnd.nextDouble(), 0.3 + 0.7 * rnd.nextDouble(), rnd, i))
    val timing = DramTiming(Seq(3, 40, 300)(seed % 3), 0.3 + 0.7 * rnd.nextDouble(), 0.5 + 0.5 * rnd.nextDouble())
    val dram = new DramModel(down, mem, timing, rnd)
    val grants = () => {
      if (down.req.valid.peek().litToBoolean && down.req.ready.peek().litToBoolean) {
        val src = (down.req.bits.id.peek().litValue >> idBits).toInt
        clients.filter(k => k.index != src && k.waiting).foreach(_.othersWhileWaiting += 1)
      }
      false
    }
    // The grant is counted before the clients see their own handshakes this cycle.
    MemSim.run(clock, clients.map(k => () => k.drive()) :+ (() => dram.drive()),
      (grants +: clients.map(k => () => k.observe())) :+ (() => dram.observe()), clients.forall(_.done))
    (clients, dram, timing, busy)
  }

  // Ports of one shape, and the shapes of the MAPM's memory clients (two L2s with 4-beat lines
  // and different id widths, the SOQ cache with 2-beat lines).
  private val mixed = Seq(up, up.copy(idBits = 3, maxBeats = 2), up.copy(idBits = 1))
  for ((ports, limit) <- Seq((Seq.fill(3)(up), 4), (Seq.fill(4)(up), 16), (mixed, 6)))
    test(s"${ports.size} ports ${ports.map(p => s"${p.idBits}b/${p.maxBeats}x").mkString(",")}, at most $limit in flight: " +
      "routing, limit, round-robin over 16 seeds") {
    val n = ports.size
    simulate(new MemArbiter(ports, limit)) { c =>
      c.clock.setTimeout(0)
      for (seed <- 0 until 16) {
        val (clients, dram, timing, busy) = runSeed(c.clock, c.reset, c.io.up, c.io.down, ports.map(_.idBits).max, 150, seed, new Random(seed))
        val what = s"seed $seed, $timing"
        assert(dram.requests.size == 150 * n, what)
        assert(dram.maxOutstanding <= limit, s"${dram.maxOutstanding} in flight, $what")
        if (timing.maxLatency == 300) assert(dram.maxOutstanding == limit, s"limit never reached, $what")
        clients.foreach(k => assert(k.worstWait <= n - 1, s"port ${k.index} saw ${k.worstWait} other grants while waiting, $what"))
        if (busy) assert(clients.map(_.worstWait).max == n - 1, s"busy ports each wait their turn, $what")
      }
    }
  }

  test("a response whose id names no requester, or a last beat with nothing in flight, is flagged and the beat dropped") {
    simulate(new MemArbiter(Seq.fill(3)(up), 4)) { c =>
      c.io.up.foreach { u => u.req.valid.poke(false.B); u.resp.ready.poke(false.B) }
      c.io.down.req.ready.poke(true.B)
      c.io.down.resp.valid.poke(false.B)
      MemSim.reset(c.clock, c.reset)
      // Source 3 of a 3-port arbiter: no requester. Taken at once (never stalls the port), seen by none.
      c.io.down.resp.valid.poke(true.B)
      c.io.down.resp.bits.id.poke((3 << up.idBits).U)
      c.io.down.resp.bits.last.poke(false.B)
      assert(c.io.down.resp.ready.peek().litToBoolean && c.io.up.forall(!_.resp.valid.peek().litToBoolean))
      assert(!c.io.protocolError.peek().litToBoolean)
      c.clock.step()
      c.io.down.resp.valid.poke(false.B)
      assert(c.io.protocolError.peek().litToBoolean, "sticky from the cycle after")
      c.clock.step(3)
      assert(c.io.protocolError.peek().litToBoolean)
    }
    simulate(new MemArbiter(Seq.fill(2)(up), 4)) { c =>
      c.io.up.foreach { u => u.req.valid.poke(false.B); u.resp.ready.poke(true.B) }
      c.io.down.req.ready.poke(true.B)
      c.io.down.resp.valid.poke(false.B)
      MemSim.reset(c.clock, c.reset)
      c.clock.step()
      assert(!c.io.protocolError.peek().litToBoolean)
      c.io.down.resp.valid.poke(true.B) // a last beat for port 1, with no request in flight
      c.io.down.resp.bits.id.poke((1 << up.idBits).U)
      c.io.down.resp.bits.last.poke(true.B)
      c.clock.step()
      c.io.down.resp.valid.poke(false.B)
      assert(c.io.protocolError.peek().litToBoolean)
    }
  }

  for ((n, fanIn) <- Seq((12, 4), (9, 8), (8, 2)))
    test(s"a tree of $n ports in groups of $fanIn: every beat routed to its port and id, the limit held, each port served within 2n grants") {
      simulate(new MemArbiterTree(up, n, 8, fanIn)) { c =>
        c.clock.setTimeout(0)
        assert(c.io.down.p == MemArbiter.downParams(Seq.fill(n)(up)), "the flat arbiter's shared port")
        for (seed <- 0 until 6) {
          val (clients, dram, timing, _) = runSeed(c.clock, c.reset, c.io.up, c.io.down, up.idBits, 60, seed, new Random(100 + seed))
          val what = s"seed $seed, $timing"
          assert(dram.requests.size == 60 * n, what)
          assert(dram.maxOutstanding <= 8, s"${dram.maxOutstanding} in flight, $what")
          clients.foreach(k => assert(k.worstWait <= 2 * n, s"port ${k.index} saw ${k.worstWait} other grants while waiting, $what"))
        }
      }
    }
}
