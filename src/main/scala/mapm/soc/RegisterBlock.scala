package mapm.soc

import chisel3._
import chisel3.util._
import mapm.axi.Axi4Lite
import mapm.format.{Access, CounterSet, RegisterMap}

/** The frame pass's configuration as the registers hold it (docs/coprocessor.md). */
class PassConfig extends Bundle {
  val nodeBase = UInt(64.W)
  val photonBase = UInt(64.W)
  val queryBase = UInt(64.W)
  val streamBase = UInt(64.W)
  val frameBase = UInt(64.W)
  val radius = UInt(64.W)
  val nodeCount = UInt(32.W)
  val queryCount = UInt(32.W)
  val pixelBase = UInt(32.W)
  val pixelCount = UInt(32.W)
  val frameScale = SInt(32.W)
  /** QUERY_ORDER.stream: the queries' order from the stream array, else the query array's. */
  val useStream = Bool()
}

/** The coprocessor's AXI4-Lite register port, decoded from [[RegisterMap]] (the one definition the
  * C header and the documentation are written from): identification values, control (a START
  * pulse), status, the interrupt's enable and status, the error causes, the pass's configuration
  * (held; writes while busy are ignored) and the counters (reading a counter's low word latches its
  * high word). An address outside the map answers SLVERR (reads 0).
  *
  * One access at a time per direction: a write is taken when AW and W are both valid, its B held
  * until taken; a read's R likewise. `irq` is IRQ_STATUS.done and IRQ_ENABLE.done.
  *
  * Latency: B or R the cycle after the address. Throughput: one read and one write per two cycles.
  */
class RegisterBlock(ident: Map[String, BigInt]) extends Module {
  override def desiredName = "RegisterBlock_v" + RegisterMap.Version
  private val addrBits = log2Ceil(RegisterMap.SpaceBytes)
  private val counterCount = CounterSet.Names.size

  val io = IO(new Bundle {
    val lite = Flipped(new Axi4Lite(addrBits))
    val config = Output(new PassConfig)
    val start = Output(Bool())
    val busy = Input(Bool())
    val done = Input(Bool())
    val error = Input(Bool())
    val errorCause = Input(UInt(RegisterMap.causes.size.W))
    /** A pass ended this cycle (sets IRQ_STATUS.done). */
    val ended = Input(Bool())
    val counters = Input(Vec(counterCount, UInt(64.W)))
    val irq = Output(Bool())
  })

  private val cfg = RegInit(0.U.asTypeOf(new PassConfig))
  private val irqEnable = RegInit(false.B)
  private val irqStatus = RegInit(false.B)
  private val shadow = RegInit(0.U(32.W))
  io.config := cfg
  io.irq := irqStatus && irqEnable

  private val streamBit = RegisterMap("QUERY_ORDER").field("stream").lsb
  /** The configuration registers by name: their 32-bit words. */
  private val cfgWords: Map[String, Seq[UInt]] = {
    def w64(x: UInt) = Seq(x(31, 0), x(63, 32))
    Map("NODE_BASE" -> w64(cfg.nodeBase), "PHOTON_BASE" -> w64(cfg.photonBase), "QUERY_BASE" -> w64(cfg.queryBase),
      "STREAM_BASE" -> w64(cfg.streamBase), "FRAME_BASE" -> w64(cfg.frameBase), "RADIUS" -> w64(cfg.radius),
      "NODE_COUNT" -> Seq(cfg.nodeCount), "QUERY_COUNT" -> Seq(cfg.queryCount), "PIXEL_BASE" -> Seq(cfg.pixelBase),
      "PIXEL_COUNT" -> Seq(cfg.pixelCount), "FRAME_SCALE" -> Seq(cfg.frameScale.asUInt), "QUERY_ORDER" -> Seq(Cat(0.U((31 - streamBit).W), cfg.useStream, 0.U(streamBit.W))))
  }
  private def setWord(name: String, word: Int, v: UInt): Unit = {
    def put64(r: UInt): UInt = if (word == 0) Cat(r(63, 32), v) else Cat(v, r(31, 0))
    name match {
      case "NODE_BASE" => cfg.nodeBase := put64(cfg.nodeBase)
      case "PHOTON_BASE" => cfg.photonBase := put64(cfg.photonBase)
      case "QUERY_BASE" => cfg.queryBase := put64(cfg.queryBase)
      case "STREAM_BASE" => cfg.streamBase := put64(cfg.streamBase)
      case "FRAME_BASE" => cfg.frameBase := put64(cfg.frameBase)
      case "RADIUS" => cfg.radius := put64(cfg.radius)
      case "NODE_COUNT" => cfg.nodeCount := v
      case "QUERY_COUNT" => cfg.queryCount := v
      case "PIXEL_BASE" => cfg.pixelBase := v
      case "PIXEL_COUNT" => cfg.pixelCount := v
      case "FRAME_SCALE" => cfg.frameScale := v.asSInt
      case "QUERY_ORDER" => cfg.useStream := v(streamBit)
    }
  }
  /** A read-only register's value: identification fields packed from `ident`, or live state. */
  private def roWord(r: mapm.format.Register, word: Int): UInt = r.name match {
    case "ID" => RegisterMap.Magic.U(32.W)
    case "STATUS" => Cat(io.error, io.done, io.busy)
    case "ERROR_CAUSE" => io.errorCause.pad(32)
    case "IRQ_ENABLE" => irqEnable.asUInt
    case "IRQ_STATUS" => irqStatus.asUInt
    case n if n.startsWith("CNT_") =>
      val k = CounterSet.Names.indexWhere(x => "CNT_" + x.toUpperCase == n)
      if (word == 0) io.counters(k)(31, 0) else shadow
    case n if r.fields.nonEmpty =>
      r.fields.foldLeft(BigInt(0)) { (acc, f) =>
        val v = ident.getOrElse(s"$n.${f.name}", BigInt(0))
        require(v >= 0 && v < (BigInt(1) << f.width), s"$n.${f.name} = $v does not fit ${f.width} bits")
        acc | (v << f.lsb)
      }.U(32.W)
    case _ => 0.U(32.W)
  }
  private val words: Seq[(Int, mapm.format.Register, Int)] =
    RegisterMap.registers.flatMap(r => (0 until r.words).map(k => (r.offset + 4 * k, r, k)))

  // Writes: AW and W together, B held until taken.
  private val bValid = RegInit(false.B)
  private val bResp = RegInit(0.U(2.W))
  private val take = io.lite.aw.valid && io.lite.w.valid && !bValid
  io.lite.aw.ready := take
  io.lite.w.ready := take
  io.lite.b.valid := bValid
  io.lite.b.bits.resp := bResp
  when(io.lite.b.fire) { bValid := false.B }
  private val wAddr = io.lite.aw.bits.addr(addrBits - 1, 2) ## 0.U(2.W)
  private val strb = io.lite.w.bits.strb
  private val start = WireInit(false.B)
  io.start := start
  when(take) {
    bValid := true.B
    bResp := Mux(VecInit(words.map { case (o, _, _) => wAddr === o.U }).asUInt.orR, 0.U, 2.U)
    for ((o, r, k) <- words) when(wAddr === o.U) {
      r.access match {
        case Access.RW if r.name == "IRQ_ENABLE" => when(strb(0)) { irqEnable := io.lite.w.bits.data(0) }
        case Access.RW => when(!io.busy) {
          val old = cfgWords(r.name)(k)
          val merged = VecInit((0 until 4).map(b => Mux(strb(b), io.lite.w.bits.data(8 * b + 7, 8 * b), old(8 * b + 7, 8 * b)))).asUInt
          setWord(r.name, k, merged)
        }
        case Access.W1P => start := strb(0) && io.lite.w.bits.data(0) && !io.busy
        case Access.W1C => when(strb(0) && io.lite.w.bits.data(0)) { irqStatus := false.B }
        case Access.RO =>
      }
    }
  }
  when(start) { irqStatus := false.B }
  // After START's clear: a pass refused at its start ends in the cycle it starts.
  when(io.ended) { irqStatus := true.B }

  // Reads: R held until taken.
  private val rValid = RegInit(false.B)
  private val rData = RegInit(0.U(32.W))
  private val rResp = RegInit(0.U(2.W))
  io.lite.ar.ready := !rValid
  io.lite.r.valid := rValid
  io.lite.r.bits.data := rData
  io.lite.r.bits.resp := rResp
  when(io.lite.r.fire) { rValid := false.B }
  private val rAddr = io.lite.ar.bits.addr(addrBits - 1, 2) ## 0.U(2.W)
  when(io.lite.ar.fire) {
    rValid := true.B
    rData := 0.U
    rResp := 2.U
    for ((o, r, k) <- words) when(rAddr === o.U) {
      rResp := 0.U
      rData := (r.access match {
        case Access.RW if r.name != "IRQ_ENABLE" => cfgWords(r.name)(k)
        case Access.W1P => 0.U
        case _ => roWord(r, k)
      })
      if (r.name.startsWith("CNT_") && k == 0) shadow := io.counters(CounterSet.Names.indexWhere(x => "CNT_" + x.toUpperCase == r.name))(63, 32)
    }
  }
}
