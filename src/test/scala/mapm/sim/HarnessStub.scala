package mapm.sim

import chisel3._
import chisel3.util._
import mapm.memory.{MemPort, MemPortParams}
import mapm.params.{MapmConfig, MapmCounters, MapmParams, QueryIn, SoResult}

/** A stand-in with the whole MAPM's top IO (docs/mapm.md) for testing the Verilator harness on its
  * own: for each query it reads the query's 32-byte record from memory (two 16-byte beats), then
  * reports one SO on port q mod ports: photon q mod 5, colour = the record's contribution bits,
  * pixel = the record's pixel,
  * flags 0, cond = (q mod 3 != 0). One query at a time. Of the counters it drives `cycles`,
  * `queries`, `tsOps` (= queries), `stallQuery` (cycles waiting for memory) and `soq_misses`
  * (= queries); the others stay 0. With `stray`, query 7's record is read from that byte address
  * instead: a faulty top, for the harness's address-range check. */
class HarnessStub(p: MapmParams, stray: Option[Long] = None) extends Module {
  override def desiredName = HarnessStub.name(p, stray)
  private val ports = p.counts.som * p.counts.soaPerSom
  private val w = p.numbers.format.width
  val io = IO(new Bundle {
    val cfg = Input(new MapmConfig(p))
    val query = Flipped(Decoupled(new QueryIn(p)))
    val mem = new MemPort(MemPortParams(p.memory.addressBits, p.memory.dataBytes, 3, 4))
    val out = Output(Vec(ports, Valid(new SoResult(p))))
    val room = Input(Vec(ports, UInt(log2Ceil(mapm.top.Mapm.resultRoom(p) + 1).W))) // unused: the stub never waits
    val done = Output(Bool())
    val error = Output(Bool())
    val counters = Output(new MapmCounters)
  })
  private val sIdle :: sReq :: sResp :: sOut :: Nil = Enum(4)
  private val state = RegInit(sIdle)
  private val q = Reg(UInt(p.indices.queryBits.W))
  private val beat = RegInit(0.U(1.W))
  private val contrib = Reg(Vec(3, UInt(w.W)))
  private val pixel = Reg(UInt(p.indices.pixelBits.W))
  private val cycles, queries, waits = RegInit(0.U(64.W))
  cycles := cycles + 1.U

  io.query.ready := state === sIdle
  when(io.query.fire) { q := io.query.bits.q; state := sReq; queries := queries + 1.U }
  io.mem.req.valid := state === sReq
  io.mem.req.bits.addr := io.cfg.queryBase + (q << 5)
  for (a <- stray) when(q === 7.U) { io.mem.req.bits.addr := a.U }
  io.mem.req.bits.id := 5.U
  io.mem.req.bits.len := 1.U
  when(io.mem.req.fire) { state := sResp; beat := 0.U }
  when(state === sResp) { waits := waits + 1.U }
  io.mem.resp.ready := state === sResp
  when(io.mem.resp.fire) {
    when(beat === 0.U) { for (c <- 0 until 3) contrib(c) := io.mem.resp.bits.data(32 * c + w - 1, 32 * c) }
    when(beat === 1.U) { pixel := io.mem.resp.bits.data(96 + p.indices.pixelBits - 1, 96) } // record byte 28
    beat := beat + 1.U
    when(io.mem.resp.bits.last) { state := sOut }
  }
  for (k <- 0 until ports) {
    val o = io.out(k)
    o.valid := state === sOut && (q % ports.U) === k.U
    o.bits.colour := contrib
    o.bits.flags := VecInit(Seq.fill(3)(0.U(3.W)))
    o.bits.cond := (q % 3.U) =/= 0.U
    o.bits.q := q
    o.bits.pixel := pixel
    o.bits.photon := q % 5.U
  }
  when(state === sOut) { state := sIdle }
  io.done := state === sIdle
  io.error := io.mem.resp.fire && io.mem.resp.bits.id =/= 5.U
  io.counters.elements.values.foreach(_ := 0.U)
  io.counters.cycles := cycles
  io.counters.queries := queries
  io.counters.tsOps := queries
  io.counters.stallQuery := waits
  io.counters.soq_misses := queries
}

object HarnessStub {
  /** The stub's module name for `p` and `stray`. */
  def name(p: MapmParams, stray: Option[Long]): String = s"HarnessStub_${p.name}${stray.map(a => s"_stray$a").getOrElse("")}"
}
