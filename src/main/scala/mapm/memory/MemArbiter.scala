package mapm.memory

import chisel3._
import chisel3.util._
import chisel3.experimental.hierarchy.{instantiable, public}

/** Shares one memory port among `n` requesters (the caches) in round-robin order.
  *
  * The requesters' ports may differ in id width and longest request (e.g. an L2 fetching 4-beat
  * lines beside the SOQ cache fetching 2-beat ones) but share the address width and beat size.
  * Each request leaves with its id zero-extended to the widest `up` id and the requester's index
  * on top, so response beats route back by id alone: `down` has `log2Ceil(n)` more id bits than the
  * widest `up` port, and takes requests as long as the longest `up` port's. A
  * request, once presented on `down`, stays unchanged until it is taken (the grant is held), and
  * the next grant goes to the first requester after the last one served. At most `maxOutstanding`
  * requests are in flight on `down` (counted from request to last beat); further requests wait.
  * A response beat waits when its requester is not ready (only that requester's port stalls).
  *
  * Latency: none (combinational paths from `up` to `down` and back). Throughput: one request and
  * one response beat per cycle.
  */
@instantiable
class MemArbiter(val ups: Seq[MemPortParams], val maxOutstanding: Int) extends Module {
  /** `n` requesters with the same port shape. */
  def this(up: MemPortParams, n: Int, maxOutstanding: Int) = this(Seq.fill(n)(up), maxOutstanding)

  val n: Int = ups.size
  require(n >= 1, "memory arbiter needs at least one port")
  require(maxOutstanding >= 1, s"memory arbiter outstanding limit must be at least 1, got $maxOutstanding")
  require(ups.map(p => (p.addressBits, p.dataBytes)).distinct.size == 1,
    s"memory arbiter ports must share address width and beat size, got ${ups.map(p => (p.addressBits, p.dataBytes)).distinct.mkString(", ")}")
  override def desiredName = s"MemArbiter_n${n}_o$maxOutstanding"
  private val srcBits = log2Ceil(n)
  private val selBits = srcBits max 1 // width of the grant registers
  private val idBits = ups.map(_.idBits).max
  val downParams: MemPortParams = MemArbiter.downParams(ups)

  @public val io = IO(new Bundle {
    val up = MixedVec(ups.map(p => Flipped(new MemPort(p))))
    val down = new MemPort(downParams)
    /** Sticky: a response beat whose id names no requester (dropped), or a last beat with no
      * request in flight. */
    val protocolError = Output(Bool())
  })

  // Requests in flight on `down`.
  val inFlight = RegInit(0.U(log2Ceil(maxOutstanding + 1).W))
  val room = inFlight < maxOutstanding.U
  val issued = io.down.req.fire
  val retired = io.down.resp.fire && io.down.resp.bits.last
  inFlight := inFlight + issued.asUInt - (retired && inFlight =/= 0.U).asUInt

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
  /** The granted requester's field, zero-extended to `width`. */
  private def chosen(f: MemPort => UInt, width: Int): UInt =
    if (n == 1) f(io.up(0)).pad(width) else VecInit(io.up.map(f(_).pad(width)))(src)
  io.down.req.bits.addr := chosen(_.req.bits.addr, downParams.addressBits)
  io.down.req.bits.len := chosen(_.req.bits.len, downParams.lenBits)
  io.down.req.bits.id := (if (n == 1) chosen(_.req.bits.id, idBits) else Cat(src, chosen(_.req.bits.id, idBits)))
  for (i <- 0 until n) io.up(i).req.ready := room && io.down.req.ready && src === i.U
  when(io.down.req.valid) {
    held := !io.down.req.ready
    heldSrc := src
  }
  when(issued) { last := src }

  // Response beats route back by the source bits of their id; a beat for no requester is dropped.
  val respSrc = if (n == 1) 0.U else io.down.resp.bits.id(idBits + srcBits - 1, idBits)
  private val srcKnown = if (isPow2(n)) true.B else respSrc < n.U
  private val protocolError = RegInit(false.B)
  when((io.down.resp.fire && !srcKnown) || (retired && inFlight === 0.U)) { protocolError := true.B }
  io.protocolError := protocolError
  for (i <- 0 until n) {
    io.up(i).resp.valid := io.down.resp.valid && respSrc === i.U
    io.up(i).resp.bits.data := io.down.resp.bits.data
    io.up(i).resp.bits.id := io.down.resp.bits.id(ups(i).idBits - 1, 0)
    io.up(i).resp.bits.last := io.down.resp.bits.last
  }
  io.down.resp.ready := (if (n == 1) io.up(0).resp.ready else !srcKnown || VecInit(io.up.map(_.resp.ready))(respSrc))
}

object MemArbiter {
  /** The shape of the shared port of an arbiter over `ups`: their common address width and beat
    * size, the widest id plus the source bits, the longest request. */
  def downParams(ups: Seq[MemPortParams]): MemPortParams =
    MemPortParams(ups.head.addressBits, ups.head.dataBytes, ups.map(_.idBits).max + log2Ceil(ups.size), ups.map(_.maxBeats).max)
}
