package mapm.shader

import chisel3._
import chisel3.experimental.hierarchy.{Definition, Instance}
import chisel3.util._
import mapm.memory.{CacheConfig, MemPort}
import mapm.uncore.SopL2
import mapm.params.{MapmConfig, MapmParams, SoGroup, SoResult}
import mapm.util.{Counters, Index, RoundRobin, Rotate}

/** Counters of the SO block (64 bits each; docs/mapm.md). */
class SoCounters extends Bundle {
  val soIssued = UInt(64.W)
  val soPassed = UInt(64.W)
  val sopL1Hits = UInt(64.W)
  val sopL1Misses = UInt(64.W)
  val sopL2Hits = UInt(64.W)
  val sopL2Misses = UInt(64.W)
  val sopL2Conflicts = UInt(64.W)
}

/** The Shader Operation block (3.5): the [[DataBus]], `som` [[Som]]s of `soaPerSom` SOAs each,
  * and the SOP L2 behind every SOP L1 bank ([[SopL2]]: shared, or in banks with a port each on
  * `mem`).
  *
  * It takes SO groups from the TSMs whenever a SOM has room, and reports every SO on `out`:
  * SOA k of SOM j is port j * soaPerSom + k, one result per SOA per cycle, whether or not cond
  * holds. It never stalls once an SO is in a reservation station (3.7); its only back-pressure
  * is the Data bus refusing groups no SOM has room for.
  *
  * Latency: Data bus (0) + SOM lane (fetch, SOA). Throughput: one SO per SOA per cycle.
  */
class SoBlock(p: MapmParams) extends Module {
  private val t = p.counts.tsm
  private val s = p.counts.som
  private val a = p.counts.soaPerSom
  override def desiredName = s"SoBlock_s${s}_a${a}_${p.numbers.format.name}_g${p.numbers.guardDigits}"
  val l2Config: CacheConfig = SoBlock.l2Config(p)
  private val banks = p.uncore.sopL2.banks

  val io = IO(new Bundle {
    val cfg = Input(new MapmConfig(p))
    val in = Vec(t, Flipped(Decoupled(new SoGroup(p))))
    val out = Vec(s * a, Valid(new SoResult(p)))
    val mem = Vec(banks, new MemPort(l2Config.down))
    val idle = Output(Bool())
    val error = Output(Bool())
    val counters = Output(new SoCounters)
  })

  val bus = Module(new DataBus(p))
  bus.io.in <> io.in
  val soms: Seq[Instance[Som]] = { val d = Definition(new Som(p)); Seq.fill(s)(Instance(d)) } // elaborated once
  val l2 = Module(new SopL2(p, SomLane.l1Config(p).down))
  io.mem <> l2.io.mem

  for ((m, j) <- soms.zipWithIndex) {
    m.io.h := io.cfg.h
    m.io.photonBase := io.cfg.photonBase
    m.io.in := bus.io.out(j)
    bus.io.free(j) := m.io.free
    for (k <- 0 until a) {
      l2.io.l1(j * a + k) <> m.io.mem(k)
      io.out(j * a + k) := m.io.out(k)
    }
  }
  io.idle := soms.map(_.io.idle).reduce(_ && _)
  io.error := l2.io.protocolError || soms.map(_.io.error).reduce(_ || _)

  import Counters.{count => counter}
  io.counters.soIssued := counter(soms.flatMap(_.io.issued))
  io.counters.soPassed := counter(io.out.map(o => o.valid && o.bits.cond))
  io.counters.sopL1Hits := Counters.sum(soms.flatMap(_.io.l1.map(_.hits)))
  io.counters.sopL1Misses := Counters.sum(soms.flatMap(_.io.l1.map(_.misses)))
  io.counters.sopL2Hits := l2.io.counters.hits
  io.counters.sopL2Misses := l2.io.counters.misses
  io.counters.sopL2Conflicts := l2.io.counters.conflicts
}

object SoBlock {
  /** One bank of the SOP L2 (the whole L2 when shared): [[SopL2.bankConfig]] under the SOP L1 banks. */
  def l2Config(p: MapmParams): CacheConfig = SopL2.bankConfig(p, SomLane.l1Config(p).down)
}
