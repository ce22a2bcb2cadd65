package mapm.shader

import chisel3._
import chisel3.experimental.hierarchy.{Definition, Instance}
import chisel3.util._
import mapm.memory.MemPort
import mapm.params.{MapmConfig, MapmParams, SoGroup, SoResult}
import mapm.uncore.Shapes
import mapm.util.{CostBlock, Counters}

/** Counters of the SO block (64 bits each; docs/mapm.md). */
class SoCounters extends Bundle {
  val soIssued = UInt(64.W)
  val soPassed = UInt(64.W)
  val sopL1Hits = UInt(64.W)
  val sopL1Misses = UInt(64.W)
}

/** The Shader Operation block (3.5): `som` [[Som]]s of `soaPerSom` SOAs each, every SOA with its
  * reservation station and its bank of its SOM's SOP L1. The Data bus in front of it and the SOP
  * L2 behind it are the uncore's ([[mapm.uncore.Uncore]]).
  *
  * SOM j takes the group on `in(j)` (the Data bus hands it one only when `free(j)` says it fits)
  * and reports every SO on `out`: SOA k of SOM j is port j * soaPerSom + k, one result per SOA per
  * cycle, whether or not cond holds. It never stalls once an SO is in a reservation station (3.7).
  * SOP L1 bank k of SOM j misses on `l1(j * soaPerSom + k)`.
  *
  * Latency: that of a SOM lane (fetch, SOA). Throughput: one SO per SOA per cycle.
  */
class SoBlock(p: MapmParams) extends Module {
  private val s = p.counts.som
  private val a = p.counts.soaPerSom
  override def desiredName = s"SoBlock_s${s}_a${a}_${p.numbers.format.name}_g${p.numbers.guardDigits}"
  CostBlock.tag(this, CostBlock.SoBlock)
  private val shapes = Shapes(p)

  val io = IO(new Bundle {
    val cfg = Input(new MapmConfig(p))
    val in = Input(Vec(s, Valid(new SoGroup(p))))
    val free = Output(Vec(s, Vec(a, UInt(log2Ceil(p.rsPerSoa + 1).W))))
    val out = Vec(s * a, Valid(new SoResult(p)))
    /** Results the consumer of each port of `out` can still take ([[SomLane]]). */
    val room = Input(Vec(s * a, UInt(log2Ceil(SomLane.resultFifo(p) + 1).W)))
    val l1 = Vec(s * a, new MemPort(shapes.sopL1.down))
    val idle = Output(Bool())
    val error = Output(Bool())
    val counters = Output(new SoCounters)
  })

  val soms: Seq[Instance[Som]] = { val d = Definition(new Som(p)); Seq.fill(s)(Instance(d)) } // elaborated once

  for ((m, j) <- soms.zipWithIndex) {
    m.io.h := io.cfg.h
    m.io.photonBase := io.cfg.photonBase
    m.io.in := io.in(j)
    io.free(j) := m.io.free
    for (k <- 0 until a) {
      io.l1(j * a + k) <> m.io.mem(k)
      io.out(j * a + k) := m.io.out(k)
      m.io.room(k) := io.room(j * a + k)
    }
  }
  io.idle := soms.map(_.io.idle).reduce(_ && _)
  io.error := soms.map(_.io.error).reduce(_ || _)

  import Counters.{count => counter}
  io.counters.soIssued := counter(soms.flatMap(_.io.issued))
  io.counters.soPassed := counter(io.out.map(o => o.valid && o.bits.cond))
  io.counters.sopL1Hits := counter(soms.flatMap(_.io.l1.map(_.hit)))
  io.counters.sopL1Misses := counter(soms.flatMap(_.io.l1.map(_.miss)))
}
