package mapm.soc

import chisel3._
import chisel3.util._
import mapm.axi.{Axi4, Axi4Checker, Axi4Lite, Axi4Params, Axi4ReadBridge}
import mapm.format.{CounterSet, RegisterMap}
import mapm.memory.MemArbiter
import mapm.numerics.Arith
import mapm.params.{Fidelity, MapmParams, SoResult}
import mapm.format.SlotLayout
import mapm.top.Mapm
import mapm.util.CostBlock

/** The MAPM as the dissertation's coprocessor (3.2, docs/coprocessor.md): driven through an AXI4-Lite
  * register port ([[RegisterBlock]], [[RegisterMap]]), it reads its query stream ([[StreamReader]]),
  * runs the queries through the MAPM ([[Mapm]]), adds every passing SO's colour into its pixel
  * ([[FrameAccumulator]]), writes the pass's pixels into the frame buffer ([[FrameWriter]]), and
  * then raises done and, if enabled, the level interrupt `irq`. Everything it reads and writes goes
  * through one AXI4 master (`axi`), watched by an [[Axi4Checker]]: a rule the memory breaks ends the
  * pass with AXI_PROTOCOL; one this design breaks fails an assertion.
  *
  * A pass: START checks the configuration ([[PassCheck]]; a bad one ends the pass at once with
  * its causes), resets the MAPM, the stream reader and the accumulator, clears the accumulator and
  * runs until every query has finished and every result is in its pixel; then the writer writes
  * the pixels and the pass ends when the last write is answered. A malformed record, an error
  * response to a read or a broken rule on the read side ends the pass early: the MAPM is held in
  * reset and the reads outstanding are drained (their beats dropped) before it ends. Query
  * indices beyond the count, pixels outside the pass and refused colours do not stop it; they are
  * reported at its end. `trace` shows every SO result (the per-SO check of the harness).
  *
  * Latency: a pass takes the MAPM's cycles plus the clear (2^tileLog2 / banks cycles, overlapped
  * with the first reads) and the write-out (about one cycle per pixel). Throughput: the MAPM's.
  */
class MapmCoproc(val p: MapmParams) extends Module {
  val axiParams: Axi4Params = MapmCoproc.axiParams(p)
  override def desiredName = s"MapmCoproc_${p.name}"
  private val lanes = p.counts.som * p.counts.soaPerSom

  val io = IO(new Bundle {
    val axi = new Axi4(axiParams)
    val ctrl = Flipped(new Axi4Lite(log2Ceil(RegisterMap.SpaceBytes)))
    val irq = Output(Bool())
    val trace = Output(Vec(lanes, Valid(new SoResult(p))))
  })

  val regs = Module(new RegisterBlock(MapmCoproc.ident(p, axiParams)))
  regs.io.lite <> io.ctrl
  io.irq := regs.io.irq
  private val cfg = regs.io.config

  // The pass's state machine.
  private val sIdle :: sRun :: sDrain :: sWrite :: sAbort :: Nil = Enum(5)
  private val state = RegInit(sIdle)
  private val done = RegInit(false.B)
  private val cause = RegInit(0.U(RegisterMap.causes.size.W))
  private val passReset = WireInit(false.B)

  // The MAPM, the stream reader and the accumulator restart with every pass.
  private val (core, reader, acc, arb) = withReset(reset.asBool || passReset) {
    val core = Module(new Mapm(p))
    val reader = Module(new StreamReader(p))
    val acc = Module(new FrameAccumulator(p))
    val arb = Module(new MemArbiter(Seq(core.memParams, reader.memParams), p.memory.maxOutstanding))
    (core, reader, acc, arb)
  }
  val bridge = Module(new Axi4ReadBridge(arb.io.down.p, axiParams, p.memory.maxOutstanding))
  val writer = Module(new FrameWriter(p, axiParams))
  val checker = Module(new Axi4Checker(axiParams, p.memory.maxOutstanding, FrameWriter.MaxWrites))
  val check = Module(new PassCheck(p))
  check.io.config := cfg
  CostBlock.tag(this, CostBlock.Coproc)
  for (m <- Seq(regs, reader, acc, arb, bridge, writer, checker, check)) CostBlock.tag(m, CostBlock.Coproc)

  core.io.cfg.h := cfg.radius(p.numbers.format.width - 1, 0)
  core.io.cfg.nodeBase := cfg.nodeBase
  core.io.cfg.photonBase := cfg.photonBase
  core.io.cfg.queryBase := cfg.queryBase
  core.io.cfg.nodeCount := cfg.nodeCount
  core.io.query <> reader.io.out
  core.io.room := acc.io.room
  acc.io.results := core.io.out
  io.trace := core.io.out
  arb.io.up(0) <> core.io.mem
  arb.io.up(1) <> reader.io.mem
  bridge.io.mem <> arb.io.down
  io.axi.ar <> bridge.io.ar
  bridge.io.r <> io.axi.r
  io.axi.aw <> writer.io.aw
  io.axi.w <> writer.io.w
  writer.io.b <> io.axi.b

  reader.io.streamBase := cfg.streamBase
  reader.io.useStream := cfg.useStream
  reader.io.queryCount := cfg.queryCount
  acc.io.scale := cfg.frameScale
  acc.io.pixelBase := cfg.pixelBase
  acc.io.pixelCount := cfg.pixelCount
  writer.io.frameBase := cfg.frameBase
  writer.io.pixelBase := cfg.pixelBase
  writer.io.pixelCount := cfg.pixelCount
  writer.io.scale := cfg.frameScale
  acc.io.read := writer.io.read
  writer.io.readOut := acc.io.readOut

  private val ax = checker.io.axi
  ax.aw.valid := io.axi.aw.valid; ax.aw.ready := io.axi.aw.ready; ax.aw.bits := io.axi.aw.bits
  ax.w.valid := io.axi.w.valid; ax.w.ready := io.axi.w.ready; ax.w.bits := io.axi.w.bits
  ax.b.valid := io.axi.b.valid; ax.b.ready := io.axi.b.ready; ax.b.bits := io.axi.b.bits
  ax.ar.valid := io.axi.ar.valid; ax.ar.ready := io.axi.ar.ready; ax.ar.bits := io.axi.ar.bits
  ax.r.valid := io.axi.r.valid; ax.r.ready := io.axi.r.ready; ax.r.bits := io.axi.r.bits
  assert(checker.io.masterFault === 0.U, "MapmCoproc broke an AXI4 rule (Axi4Checker.MasterRules)")

  // Causes as they arise (ERROR_CAUSE bits by name).
  private def bit(name: String): Int = RegisterMap.cause(name).bit
  private val seen = Wire(Vec(RegisterMap.causes.size, Bool()))
  seen.foreach(_ := false.B)
  seen(bit("NONFINITE")) := acc.io.faults.nonFinite
  seen(bit("RANGE")) := acc.io.faults.range
  seen(bit("COUNT")) := acc.io.faults.count
  seen(bit("PIXEL")) := acc.io.faults.pixel
  seen(bit("QUERY")) := reader.io.badQuery
  seen(bit("RECORD")) := core.io.error || acc.io.overflow || arb.io.protocolError
  seen(bit("AXI_READ")) := bridge.io.readError
  seen(bit("AXI_WRITE")) := writer.io.error
  seen(bit("AXI_PROTOCOL")) := checker.io.slaveFault =/= 0.U
  private val fatal = seen(bit("RECORD")) || seen(bit("AXI_READ")) || seen(bit("AXI_PROTOCOL"))

  reader.io.start := false.B
  acc.io.clear := false.B
  writer.io.start := false.B
  bridge.io.drop := state === sAbort
  private val ended = WireInit(false.B)
  private val quiet = RegInit(0.U(2.W)) // cycles the MAPM, the reader and the accumulator have all been idle
  private val drainWait = RegInit(0.U(21.W))
  switch(state) {
    is(sIdle) {
      when(regs.io.start) {
        passReset := true.B
        done := false.B
        val bad = Seq("ALIGN" -> check.io.align, "EMPTY" -> check.io.empty, "LIMIT" -> check.io.limit, "OVERLAP" -> check.io.overlap)
        val c = bad.map { case (n, b) => b.asUInt << bit(n) }.reduce(_ | _)
        cause := c
        when(c === 0.U) { state := sRun }.otherwise { ended := true.B; done := true.B }
      }
    }
    is(sRun) {
      when(RegNext(state) =/= sRun) { reader.io.start := true.B; acc.io.clear := true.B }
      quiet := Mux(reader.io.done && core.io.done && acc.io.idle && !reader.io.start, Mux(quiet === 3.U, 3.U, quiet + 1.U), 0.U)
      when(fatal) { state := sAbort; drainWait := 0.U }.elsewhen(quiet === 2.U) { state := sWrite; writer.io.start := true.B }
    }
    is(sWrite) {
      when(writer.io.done && !writer.io.start) { state := sIdle; ended := true.B; done := true.B }
    }
    is(sAbort) {
      passReset := true.B
      drainWait := drainWait + 1.U
      when(bridge.io.outstanding === 0.U || drainWait.andR) { state := sIdle; ended := true.B; done := true.B }
    }
  }
  when(state =/= sIdle) { cause := cause | seen.asUInt }
  regs.io.busy := state =/= sIdle
  regs.io.done := done
  regs.io.error := done && cause =/= 0.U
  regs.io.errorCause := cause
  regs.io.ended := ended
  regs.io.counters := VecInit(CounterSet.Names.map(n => core.io.counters.elements(n)))
}

object MapmCoproc {
  /** The AXI4 port of configuration `p`. Its ids name the reads: the MAPM's memory port's and the
    * stream reader's, one bit above to tell them apart. */
  def axiParams(p: MapmParams): Axi4Params = {
    val readIds = MemArbiter.downParams(Seq(mapm.uncore.Shapes(p).mem, StreamReader.memParams(p))).idBits
    require(p.coproc.axiIdBits == 0 || p.coproc.axiIdBits >= readIds,
      s"AXI4 ids of ${p.coproc.axiIdBits} bits cannot name the ${1 << readIds} reads this configuration may have outstanding: give at least $readIds (or 0)")
    Axi4Params(p.memory.addressBits, p.memory.dataBytes, if (p.coproc.axiIdBits == 0) readIds else p.coproc.axiIdBits)
  }

  /** The identification registers' field values ("REGISTER.field" -> value) for `p`. */
  def ident(p: MapmParams, ap: Axi4Params): Map[String, BigInt] = {
    val f = p.numbers.format
    val fa = p.frameAccum
    Map[String, Int]("VERSION.map" -> RegisterMap.Version,
      "HW_COUNTS.tsm" -> p.counts.tsm, "HW_COUNTS.som" -> p.counts.som, "HW_COUNTS.soa" -> p.counts.soaPerSom, "HW_COUNTS.guard" -> p.numbers.guardDigits,
      "HW_FORMAT.exp_width" -> f.expWidth, "HW_FORMAT.man_width" -> f.manWidth, "HW_FORMAT.slot_bytes" -> p.slotBytes,
      "HW_FORMAT.arith" -> (if (p.numbers.arith == Arith.Conventional) 1 else 0),
      "HW_FORMAT.layout" -> (if (p.memory.layout == SlotLayout.Wide) 1 else 0),
      "HW_FORMAT.fidelity" -> (if (p.sim.fidelity == Fidelity.Timing) 1 else 0),
      "HW_MEMORY.data_bytes" -> ap.dataBytes, "HW_MEMORY.id_bits" -> ap.idBits, "HW_MEMORY.addr_bits" -> ap.addrBits,
      "HW_FRAME.tile_log2" -> p.coproc.tileLog2, "HW_FRAME.acc_bits" -> fa.accBits, "HW_FRAME.count_bits" -> fa.countBits,
      "HW_INDICES.query_bits" -> p.indices.queryBits, "HW_INDICES.node_bits" -> p.indices.nodeBits).map { case (k, v) => k -> BigInt(v) }
  }
}
