package mapm.memory

import chisel3._
import chisel3.util._

/** Shares one memory port among `n` requesters (the caches) in round-robin order.
  *
  * Each request leaves with its id widened by the requester's index in the top bits, so response
  * beats route back by id alone: `down` has `log2Ceil(n)` more id bits than each `up` port. A
  * request, once presented on `down`, stays unchanged until it is taken (the grant is held), and
  * the next grant goes to the first requester after the last one served. At most `maxOutstanding`
  * requests are in flight on `down` (counted from request to last beat); further requests wait.
  * A response beat waits when its requester is not ready (only that requester's port stalls).
  *
  * Latency: none (combinational paths from `up` to `down` and back). Throughput: one request and
  * one response beat per cycle.
  */
class MemArbiter(val upParams: MemPortParams, val n: Int, val maxOutstanding: Int) extends Module {
  require(n >= 1, s"memory arbiter needs at least one port, got $n")
  require(maxOutstanding >= 1, s"memory arbiter outstanding limit must be at least 1, got $maxOutstanding")
  override def desiredName = s"MemArbiter_n${n}_o$maxOutstanding"
  private val srcBits = log2Ceil(n)
  private val selBits = srcBits max 1 // width of the grant registers
  val downParams: MemPortParams = upParams.widenId(srcBits)

  val io = IO(new Bundle {
    val up = Vec(n, Flipped(new MemPort(upParams)))
    val down = new MemPort(downParams)
  })

  // Requests in flight on `down`.
  val inFlight = RegInit(0.U(log2Ceil(maxOutstanding + 1).W))
  val room = inFlight < maxOutstanding.U
  val issued = io.down.req.fire
  val retired = io.down.resp.fire && io.down.resp.bits.last
  inFlight := inFlight + issued.asUInt - retired.asUInt

  // Round-robin grant, held while the granted request waits on `down`.
  val last = RegInit((n - 1).U(selBits.W))
  val held = RegInit(false.B)
  val heldSrc = Reg(UInt(selBits.W))
  val valids = VecInit(io.up.map(_.req.valid)).asUInt
  // The first requester above the last grant, else the first one from the bottom.
  val above = valids & VecInit((0 until n).map(i => i.U > last)).asUInt
  val pick = Mux(above.orR, PriorityEncoder(above), PriorityEncoder(valids))
  val src = Mux(held, heldSrc, pick)
  val any = valids.orR

  io.down.req.valid := room && any
  private def chosen[T <: Data](f: MemPort => T): T = if (n == 1) f(io.up(0)) else VecInit(io.up.map(f))(src)
  io.down.req.bits.addr := chosen(_.req.bits.addr)
  io.down.req.bits.len := chosen(_.req.bits.len)
  io.down.req.bits.id := (if (n == 1) io.up(0).req.bits.id else Cat(src, chosen(_.req.bits.id)))
  for (i <- 0 until n) io.up(i).req.ready := room && io.down.req.ready && src === i.U
  when(io.down.req.valid) {
    held := !io.down.req.ready
    heldSrc := src
  }
  when(issued) { last := src }

  // Response beats route back by the source bits of their id.
  val respSrc = if (n == 1) 0.U else io.down.resp.bits.id(upParams.idBits + srcBits - 1, upParams.idBits)
  for (i <- 0 until n) {
    io.up(i).resp.valid := io.down.resp.valid && respSrc === i.U
    io.up(i).resp.bits.data := io.down.resp.bits.data
    io.up(i).resp.bits.id := io.down.resp.bits.id(upParams.idBits - 1, 0)
    io.up(i).resp.bits.last := io.down.resp.bits.last
  }
  io.down.resp.ready := (if (n == 1) io.up(0).resp.ready else VecInit(io.up.map(_.resp.ready))(respSrc))
}
