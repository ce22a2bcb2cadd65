package mapm.axi

import chisel3._
import chisel3.util._
import mapm.memory.{MemPort, MemPortParams, RegFifo}

/** The MAPM's read port ([[MemPort]], docs/memory-port.md) on the read channels of an AXI4
  * master: each request becomes one INCR burst of `len + 1` full beats under the request's id
  * (zero-extended), each R beat a response beat. The memory port's rules make the bursts AXI4's:
  * requests are aligned to their size (at most 64 bytes), so none crosses 4 KiB, and ids are
  * unique among outstanding requests.
  *
  * AR leaves from a two-entry register FIFO, so ARVALID never depends on ARREADY in the same
  * cycle. An R beat with SLVERR or DECERR is passed on and sets the sticky `readError`. While
  * `drop` is high (the controller ends a pass early and resets the MAPM) no request is taken and
  * R beats are taken and discarded, so the reads outstanding drain; `outstanding` counts the
  * requests taken whose last beat has not come back.
  *
  * Latency: one cycle from request to AR; none from R to response. Throughput: one request and one
  * beat a cycle.
  */
class Axi4ReadBridge(mp: MemPortParams, ap: Axi4Params, maxOutstanding: Int) extends Module {
  require(mp.dataBytes == ap.dataBytes, s"the read port's ${mp.dataBytes}-byte beats must be the AXI4 port's ${ap.dataBytes}")
  require(mp.idBits <= ap.idBits, s"the read port's ${mp.idBits}-bit ids do not fit the AXI4 port's ${ap.idBits}")
  require(mp.addressBits <= ap.addrBits, s"the read port's ${mp.addressBits}-bit addresses do not fit the AXI4 port's ${ap.addrBits}")
  require(mp.maxBeats <= Axi4.MaxBeats, s"a request of ${mp.maxBeats} beats is longer than an AXI4 burst")
  override def desiredName = s"Axi4ReadBridge_id${ap.idBits}_d${ap.dataBytes}"

  val io = IO(new Bundle {
    val mem = Flipped(new MemPort(mp))
    val ar = Decoupled(new Axi4Addr(ap))
    val r = Flipped(Decoupled(new Axi4R(ap)))
    val drop = Input(Bool())
    val readError = Output(Bool())
    val outstanding = Output(UInt(log2Ceil(maxOutstanding + 1).W))
  })

  private val arQ = Module(new RegFifo(new Axi4Addr(ap), 2))
  arQ.io.enq.valid := io.mem.req.valid && !io.drop
  io.mem.req.ready := arQ.io.enq.ready && !io.drop
  private val ar = arQ.io.enq.bits
  ar.id := io.mem.req.bits.id
  ar.addr := io.mem.req.bits.addr
  ar.len := io.mem.req.bits.len
  ar.size := ap.sizeCode.U
  ar.burst := Axi4.BurstIncr
  ar.lock := false.B
  ar.cache := "b0011".U // normal, non-cacheable, bufferable
  ar.prot := 0.U
  ar.qos := 0.U
  io.ar <> arQ.io.deq

  io.mem.resp.valid := io.r.valid && !io.drop
  io.mem.resp.bits.data := io.r.bits.data
  io.mem.resp.bits.id := io.r.bits.id
  io.mem.resp.bits.last := io.r.bits.last
  io.r.ready := io.mem.resp.ready || io.drop

  private val error = RegInit(false.B)
  when(io.r.fire && io.r.bits.resp(1)) { error := true.B }
  io.readError := error
  private val outstanding = RegInit(0.U(log2Ceil(maxOutstanding + 1).W))
  private val ends = io.r.fire && io.r.bits.last && outstanding =/= 0.U // a spurious RLAST is the checker's to flag
  outstanding := outstanding + io.mem.req.fire.asUInt - ends.asUInt
  io.outstanding := outstanding
}
