package mapm.uncore

import chisel3._
import chisel3.util._
import mapm.memory.{MemArbiter, MemPort}
import mapm.params.{MapmParams, SoBus, SoGroup}
import mapm.util.{CostBlock, Counters}

/** Counters of the uncore (64 bits each; docs/mapm.md). */
class UncoreCounters extends Bundle {
  val tsL2 = new L2Counters
  val sopL2 = new L2Counters
  val bytesFetched = UInt(64.W)
}

/** The memory system and interconnect of the MAPM (docs/uncore.md): everything between the
  * blocks' L1 caches and SO-group ports and the memory port.
  *
  *  - the TS L2 ([[L2]] under the TSMs' TS L1s) and the SOP L2 ([[L2]] under the SOP L1 banks),
  *    each shared (Table 4.2's) or in address-interleaved banks, as `p.uncore` says;
  *  - the memory arbiter ([[MemArbiter]]) in front of the memory port, over the TS L2's banks, the
  *    SOQ cache and the SOP L2's banks ([[Shapes.memClients]]), with at most
  *    `memory.maxOutstanding` requests in flight;
  *  - the Data bus, which hands the TSMs' SO groups to SOMs with room for them: the dissertation's
  *    [[DataBus]] or the staged [[RingBus]], as `p.uncore.soBus` says.
  *
  * The blocks own their L1s ([[mapm.tsearch.TsBlock]]: TS L1s and the SOQ cache;
  * [[mapm.shader.SoBlock]]: the SOP L1 banks) and see the uncore only through typed ports whose
  * shapes come from [[Shapes]]. `idle` is high while no memory request is outstanding.
  *
  * Latency: the serial Data bus none (combinational), the ring bus [[RingBus]]'s; an L2 hit that of
  * [[L2]]; the memory arbiter none.
  * Throughput: one request a cycle per L2 bank, one request a cycle on the memory port,
  * min(TSMs, SOMs) SO groups a cycle on the Data bus.
  */
class Uncore(p: MapmParams) extends Module {
  private val t = p.counts.tsm
  private val s = p.counts.som
  private val a = p.counts.soaPerSom
  val shapes: Shapes = Shapes(p)
  override def desiredName = s"Uncore_t${t}_s${s}_a${a}_ts${p.uncore.tsL2.name}_sop${p.uncore.sopL2.name}" +
    (if (p.uncore.soBus == SoBus.Serial) "" else s"_${p.uncore.soBus.name}")
  CostBlock.tag(this, CostBlock.Uncore)

  val io = IO(new Bundle {
    /** The TSMs' TS L1 miss ports. */
    val tsL1 = Vec(t, Flipped(new MemPort(shapes.tsL1.down)))
    /** The SOQ cache's miss port. */
    val soq = Flipped(new MemPort(shapes.soq.down))
    /** The SOP L1 banks' miss ports: SOA k of SOM j is port j * a + k. */
    val sopL1 = Vec(s * a, Flipped(new MemPort(shapes.sopL1.down)))
    /** The TSMs' SO groups. */
    val groups = Vec(t, Flipped(Decoupled(new SoGroup(p))))
    /** Each SOM's lanes' free reservation-station entries. */
    val free = Input(Vec(s, Vec(a, UInt(log2Ceil(p.rsPerSoa + 1).W))))
    /** The group each SOM takes this cycle. */
    val som = Output(Vec(s, Valid(new SoGroup(p))))
    val mem = new MemPort(shapes.mem)
    val idle = Output(Bool())
    val protocolError = Output(Bool())
    val counters = Output(new UncoreCounters)
  })

  val tsL2 = Module(new L2("ts", t, shapes.tsL1.down, shapes.tsL2, p.uncore.tsL2))
  val sopL2 = Module(new L2("sop", s * a, shapes.sopL1.down, shapes.sopL2, p.uncore.sopL2))
  tsL2.io.l1 <> io.tsL1
  sopL2.io.l1 <> io.sopL1

  val arb = Module(new MemArbiter(shapes.memClients, p.memory.maxOutstanding))
  private val ups = tsL2.io.mem ++ Seq(io.soq) ++ sopL2.io.mem
  for ((u, i) <- ups.zipWithIndex) arb.io.up(i) <> u
  io.mem <> arb.io.down

  val bus: SoBusIO = p.uncore.soBus match {
    case SoBus.Serial => Module(new DataBus(p)).io
    case SoBus.Ring => Module(new RingBus(p)).io
  }
  bus.in <> io.groups
  bus.free := io.free
  io.som := bus.out

  // Requests outstanding on the memory port (request taken to last beat).
  private val outstanding = RegInit(0.U(log2Ceil(p.memory.maxOutstanding + 1).W))
  outstanding := outstanding + io.mem.req.fire.asUInt - (io.mem.resp.fire && io.mem.resp.bits.last).asUInt
  io.idle := outstanding === 0.U
  io.protocolError := tsL2.io.protocolError || sopL2.io.protocolError || arb.io.protocolError

  io.counters.tsL2 := tsL2.io.counters
  io.counters.sopL2 := sopL2.io.counters
  io.counters.bytesFetched := (Counters.count(Seq(io.mem.resp.fire)) << log2Ceil(p.memory.dataBytes))(63, 0)
}
