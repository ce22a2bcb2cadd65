package mapm.memory

import chisel3._
import chiseltest._
import scala.collection.mutable.ArrayBuffer
import scala.util.Random

/** Memory contents, byte addressed from 0: given bytes, or `size` random ones. */
final class MemImage(val bytes: Array[Byte]) {
  def this(size: Int, seed: Long) = this({ val r = new Random(seed); Array.fill(size)(r.nextInt(256).toByte) })
  val size: Int = bytes.length

  /** `n` bytes from `addr`, little-endian (byte addr + j is bits 8j+7..8j). */
  def read(addr: Long, n: Int): BigInt = {
    require(addr >= 0 && addr + n <= size, s"read of $n bytes at $addr outside the $size-byte image")
    (0 until n).foldLeft(BigInt(0))((acc, j) => acc | (BigInt(bytes((addr + j).toInt) & 0xff) << (8 * j)))
  }
}

/** How a behavioural memory behaves: latency drawn uniformly from 0..maxLatency cycles per request,
  * and per-cycle probabilities of taking a request and of presenting a response beat. */
final case class DramTiming(maxLatency: Int, reqReady: Double, respValid: Double) {
  override def toString: String = f"latency 0..$maxLatency, req ready $reqReady%.2f, resp valid $respValid%.2f"
}

/** The host side of a [[MemPort]]: a behavioural DRAM playing the responder on `port` (the DUT's
  * requester view), cycle by cycle.
  *
  * Each accepted request becomes ready `1 + latency` cycles later. Whenever no beat is on offer the
  * model, with probability `respValid`, offers the next beat of a random ready request, so answers
  * to different ids come back in any order and their beats interleave, while the beats of one
  * request stay in order. An offered beat stays unchanged until taken. The model checks the
  * requester's side of the protocol: ids unique among outstanding requests, aligned in-range
  * addresses, lengths within the port, requests held stable until taken.
  *
  * Per cycle: [[drive]] (pokes), then [[observe]] (peeks the handshakes), then the clock steps.
  */
final class DramModel(port: MemPort, mem: MemImage, timing: DramTiming, rnd: Random) {
  private final class Pending(val id: BigInt, val addr: Long, val beats: Int, val readyAt: Long) { var next = 0 }
  private val p = port.p
  private val pending = ArrayBuffer[Pending]()
  private var offered: Option[Pending] = None
  private var reqReady = false
  private var waitingReq: Option[(BigInt, BigInt, BigInt)] = None
  private var cycle = 0L

  /** Addresses of the requests taken, in order. */
  val requests = ArrayBuffer[Long]()
  /** Most requests outstanding at once. */
  var maxOutstanding = 0
  def outstanding: Int = pending.size

  def drive(): Unit = {
    reqReady = rnd.nextDouble() < timing.reqReady
    port.req.ready.poke(reqReady.B)
    if (offered.isEmpty && rnd.nextDouble() < timing.respValid) {
      val ready = pending.filter(_.readyAt <= cycle)
      if (ready.nonEmpty) offered = Some(ready(rnd.nextInt(ready.size)))
    }
    port.resp.valid.poke(offered.isDefined.B)
    offered.foreach { q =>
      port.resp.bits.data.poke(mem.read(q.addr + q.next.toLong * p.dataBytes, p.dataBytes).U(p.dataBits.W))
      port.resp.bits.id.poke(q.id.U(p.idBits.W))
      port.resp.bits.last.poke((q.next == q.beats - 1).B)
    }
  }

  /** Records this cycle's handshakes; true when one happened. */
  def observe(): Boolean = {
    var progress = false
    if (port.req.valid.peek().litToBoolean) {
      val req = (port.req.bits.addr.peek().litValue, port.req.bits.id.peek().litValue, port.req.bits.len.peek().litValue)
      waitingReq.foreach(w => assert(w == req, s"request $w changed to $req before it was taken"))
      if (reqReady) {
        val (addr, id, len) = req
        val beats = len.toInt + 1
        val bytes = beats * p.dataBytes
        assert(beats <= p.maxBeats, s"request for $beats beats on a ${p.maxBeats}-beat port")
        assert(addr % bytes == 0 && addr + bytes <= mem.size, s"request for $bytes bytes at $addr is unaligned or outside memory")
        assert(!pending.exists(_.id == id), s"request id $id reused while outstanding")
        pending += new Pending(id, addr.toLong, beats, cycle + 1 + rnd.nextInt(timing.maxLatency + 1))
        maxOutstanding = maxOutstanding max pending.size
        requests += addr.toLong
        waitingReq = None
        progress = true
      } else waitingReq = Some(req)
    } else assert(waitingReq.isEmpty, s"request ${waitingReq.get} withdrawn before it was taken")
    offered.foreach { q =>
      if (port.resp.ready.peek().litToBoolean) {
        q.next += 1
        if (q.next == q.beats) pending -= q
        offered = None
        progress = true
      }
    }
    cycle += 1
    progress
  }
}
