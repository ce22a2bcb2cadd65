package mapm.memory

import chisel3._
import chiseltest._
import scala.collection.mutable
import scala.util.Random

/** A client of a single-beat [[MemPort]] (the DUT's responder view `port`): reads `addrs` in order,
  * each under a random id not already outstanding, and checks every response against `mem`.
  *
  * A request is offered with probability `reqValid` per cycle and then held until taken; responses
  * are taken with probability `respReady`. Checks: each response answers an outstanding id (none
  * duplicated), carries the word at that request's address, and stays unchanged while not taken.
  * Lost responses show up as a client that never finishes (see [[MemSim.run]]).
  */
final class PortClient(port: MemPort, mem: MemImage, addrs: IndexedSeq[Long], reqValid: Double,
                       respReady: Double, rnd: Random, val name: String = "client") {
  private val p = port.p
  private val outstanding = mutable.Map[BigInt, Long]()
  private var next = 0
  private var offered: Option[(BigInt, Long)] = None
  private var takeResp = false
  private var waitingResp: Option[(BigInt, BigInt)] = None
  /** Cycle of acceptance of each outstanding id, and the latencies seen (acceptance to response). */
  private val acceptedAt = mutable.Map[BigInt, Long]()
  private var cycle = 0L
  val latencies = mutable.ArrayBuffer[Long]()
  var responses = 0

  def done: Boolean = next == addrs.size && outstanding.isEmpty && offered.isEmpty

  def drive(): Unit = {
    if (offered.isEmpty && next < addrs.size && rnd.nextDouble() < reqValid) {
      val free = (0 until (1 << p.idBits)).map(BigInt(_)).filterNot(outstanding.contains)
      if (free.nonEmpty) offered = Some((free(rnd.nextInt(free.size)), addrs(next)))
    }
    port.req.valid.poke(offered.isDefined.B)
    offered.foreach { case (id, addr) =>
      port.req.bits.addr.poke(addr.U(p.addressBits.W))
      port.req.bits.id.poke(id.U(p.idBits.W))
      port.req.bits.len.poke(0.U)
    }
    takeResp = rnd.nextDouble() < respReady
    port.resp.ready.poke(takeResp.B)
  }

  /** Records this cycle's handshakes; true when one happened. */
  def observe(): Boolean = {
    var progress = false
    offered.foreach { case (id, addr) =>
      if (port.req.ready.peek().litToBoolean) {
        outstanding(id) = addr
        acceptedAt(id) = cycle
        next += 1
        offered = None
        progress = true
      }
    }
    if (port.resp.valid.peek().litToBoolean) {
      val resp = (port.resp.bits.id.peek().litValue, port.resp.bits.data.peek().litValue)
      waitingResp.foreach(w => assert(w == resp, s"$name: response $w changed to $resp before it was taken"))
      if (takeResp) {
        val (id, data) = resp
        val addr = outstanding.getOrElse(id, fail(s"$name: response for id $id, which is not outstanding"))
        val want = mem.read(addr - addr % p.dataBytes, p.dataBytes)
        assert(data == want, s"$name: id $id address $addr: got ${data.toString(16)}, want ${want.toString(16)}")
        assert(port.resp.bits.last.peek().litToBoolean, s"$name: single-beat response without last")
        outstanding -= id
        latencies += cycle - acceptedAt.remove(id).get
        responses += 1
        waitingResp = None
        progress = true
      } else waitingResp = Some(resp)
    } else assert(waitingResp.isEmpty, s"$name: response ${waitingResp.get} withdrawn before it was taken")
    cycle += 1
    progress
  }

  private def fail(msg: String): Nothing = throw new AssertionError(msg)
}

/** The cycle loop shared by the memory tests. */
object MemSim {
  /** Steps `clock` until `done`, calling every agent's drive, then observe, each cycle. Fails when
    * `watchdog` cycles pass without any handshake, or after `limit` cycles. Returns the cycles run. */
  def run(clock: Clock, drives: Seq[() => Unit], observes: Seq[() => Boolean], done: => Boolean,
          watchdog: Int = 3000, limit: Long = 5000000L): Long = {
    var cycles = 0L
    var idle = 0
    while (!done) {
      drives.foreach(_())
      val progress = observes.map(_()).exists(identity)
      clock.step()
      cycles += 1
      idle = if (progress) 0 else idle + 1
      assert(idle < watchdog, s"watchdog: no handshake for $watchdog cycles (cycle $cycles)")
      assert(cycles < limit, s"watchdog: not done after $limit cycles")
    }
    cycles
  }

  /** Holds reset for two cycles (every agent must poke its valids low first). */
  def reset(clock: Clock, reset: Reset): Unit = {
    reset.poke(true.B)
    clock.step(2)
    reset.poke(false.B)
  }
}
