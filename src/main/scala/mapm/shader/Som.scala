package mapm.shader

import chisel3._
import chisel3.experimental.hierarchy.{Definition, Instance, instantiable, public}
import chisel3.util._
import mapm.memory.{CacheEvents, MemPort}
import mapm.params.{MapmParams, SoGroup, SoResult}
import mapm.uncore.Shapes

/** Shader Operation Module (3.5): `soaPerSom` [[SomLane]]s, each an SOA with its part of the
  * reservation station and its bank of the SOP L1. An SO goes to the lane of its photon:
  * photon index mod soaPerSom, so each bank holds its own share of the photon records.
  *
  * The Data bus hands the SOM at most one [[SoGroup]] per cycle, and only one that fits: for every
  * lane, the group's SOs for that lane are no more than the lane's free entries (`free`). The SOM
  * inserts them the cycle they arrive; it never refuses or drops one.
  *
  * Latency: that of a lane. Throughput: one group in, and one SO into each SOA, per cycle.
  */
@instantiable
class Som(p: MapmParams) extends Module {
  private val a = p.counts.soaPerSom
  /** One lane elaborated once, instantiated `a` times. */
  val lanes: Seq[Instance[SomLane]] = { val d = Definition(new SomLane(p)); Seq.fill(a)(Instance(d)) }
  override def desiredName = s"Som_${p.numbers.format.name}_g${p.numbers.guardDigits}_a${a}_r${p.rsPerSoa}"

  @public val io = IO(new Bundle {
    val h = Input(UInt(p.numbers.format.width.W))
    val photonBase = Input(UInt(p.memory.addressBits.W))
    val in = Input(Valid(new SoGroup(p)))
    val free = Output(Vec(a, UInt(log2Ceil(p.rsPerSoa + 1).W)))
    /** Results each lane's consumer can still take ([[SomLane]]). */
    val room = Input(Vec(a, UInt(log2Ceil(SomLane.resultFifo(p) + 1).W)))
    val mem = Vec(a, new MemPort(Shapes(p).sopL1.down))
    val out = Vec(a, Valid(new SoResult(p)))
    val issued = Output(Vec(a, Bool()))
    val idle = Output(Bool())
    val l1 = Output(Vec(a, new CacheEvents))
    val error = Output(Bool())
  })

  for ((l, b) <- lanes.zipWithIndex) {
    l.io.h := io.h
    l.io.photonBase := io.photonBase
    for (k <- 0 until SoGroup.Size) {
      val ph = io.in.bits.photon(k)
      l.io.insert(k).valid := io.in.valid && ph.valid && SoGroup.lane(ph.bits, a) === b.U
      l.io.insert(k).bits.query := io.in.bits.query
      l.io.insert(k).bits.photon := ph.bits
    }
    io.free(b) := l.io.free
    l.io.room := io.room(b)
    io.mem(b) <> l.io.mem
    io.out(b) := l.io.out
    io.issued(b) := l.io.issued
    io.l1(b) := l.io.l1
  }
  io.idle := lanes.map(_.io.idle).reduce(_ && _)
  io.error := lanes.map(_.io.error).reduce(_ || _)
}
