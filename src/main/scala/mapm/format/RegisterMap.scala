package mapm.format

import mapm.numerics.FrameAccum

/** How software may access a register. */
sealed abstract class Access(val name: String, val doc: String)
object Access {
  case object RO extends Access("RO", "read only; writes are ignored")
  case object RW extends Access("RW", "read and write; writes while busy are ignored")
  case object W1P extends Access("W1P", "write 1 to act; reads 0")
  case object W1C extends Access("W1C", "write 1 to clear a bit")
}

/** A field of a register: bits `lsb` to `lsb + width - 1`. */
final case class RegField(name: String, lsb: Int, width: Int, doc: String) {
  require(name.matches("[a-z][a-z0-9_]*"), s"field name $name must be a lower-case C identifier")
  require(lsb >= 0 && width >= 1 && lsb + width <= 32, s"field $name: bits $lsb..${lsb + width - 1} leave the 32-bit word")
  def mask: Long = ((1L << width) - 1) << lsb
}

/** One register of the coprocessor's AXI4-Lite port: 32 bits at `offset`, or 64 bits as two words
  * (`_LO` at `offset`, `_HI` at `offset + 4`). A register without fields is one number. */
final case class Register(name: String, offset: Int, access: Access, doc: String, fields: Seq[RegField] = Nil, bits: Int = 32) {
  require(name.matches("[A-Z][A-Z0-9_]*"), s"register name $name must be an upper-case C identifier")
  require(bits == 32 || bits == 64, s"register $name: 32 or 64 bits, got $bits")
  require(offset % (bits / 8) == 0, s"register $name: offset $offset is not aligned to its ${bits / 8} bytes")
  require(fields.map(_.name).distinct.size == fields.size, s"register $name: duplicate field names")
  require(fields.sortBy(_.lsb).sliding(2).forall { case Seq(a, b) => a.lsb + a.width <= b.lsb; case _ => true },
    s"register $name: fields overlap")
  require(bits == 32 || fields.isEmpty, s"register $name: a 64-bit register is one number")
  def words: Int = bits / 32
  def field(n: String): RegField =
    fields.find(_.name == n).getOrElse(throw new NoSuchElementException(s"register $name has no field $n"))
}

/** Why a frame ended in error: one bit of ERROR_CAUSE each. */
final case class ErrorCause(bit: Int, name: String, reason: String)

/** The MAPM coprocessor's register map (docs/coprocessor.md), defined once. The hardware's
  * AXI4-Lite register block (`mapm.soc.RegisterBlock`) decodes these offsets and fields, and the
  * documentation's table ([[markdown]]) and the C header `mapm_regs.h` ([[cHeader]]), which the C
  * driver (tools/driver) and the harness include, are written from it.
  */
object RegisterMap {
  /** ID reads these four bytes as "MAPM" in memory order. */
  val Magic: Long = "MAPM".reverse.foldLeft(0L)((v, c) => v << 8 | c.toLong)
  /** Version of this map: a driver refuses another. */
  val Version: Int = 1
  /** Bytes of the register space (AXI4-Lite addresses below it). */
  val SpaceBytes: Int = 4096
  /** Offset of the first counter: counter k of [[CounterSet.Names]] is the 64-bit register at
    * CounterBase + 8 k. */
  val CounterBase: Int = 0x100

  import Access._

  private def f(name: String, lsb: Int, width: Int, doc: String) = RegField(name, lsb, width, doc)

  /** The registers, by offset. */
  val registers: Seq[Register] = Seq(
    Register("ID", 0x000, RO, "identification: the bytes \"MAPM\" (0x" + Magic.toHexString + ")"),
    Register("VERSION", 0x004, RO, "versions", Seq(f("map", 0, 16, s"this register map's version ($Version)"))),
    Register("HW_COUNTS", 0x008, RO, "the generator's unit counts", Seq(
      f("tsm", 0, 8, "TSMs"), f("som", 8, 8, "SOMs"), f("soa", 16, 8, "SOAs per SOM"), f("guard", 24, 8, "guard digits g"))),
    Register("HW_FORMAT", 0x00c, RO, "the number format and arithmetic", Seq(
      f("exp_width", 0, 8, "exponent bits"), f("man_width", 8, 8, "fraction bits"), f("slot_bytes", 16, 8, "bytes of a value slot in the memory records"),
      f("arith", 24, 1, "0 online (digit-serial), 1 conventional"), f("layout", 25, 1, "0 packed, 1 wide slots"),
      f("fidelity", 26, 1, "0 full arithmetic, 1 the SOAs' timing model (colours not computed)"))),
    Register("HW_MEMORY", 0x010, RO, "the AXI4 master", Seq(
      f("data_bytes", 0, 8, "bytes per data beat"), f("id_bits", 8, 8, "id width"), f("addr_bits", 16, 8, "address width"))),
    Register("HW_FRAME", 0x014, RO, "the frame accumulator", Seq(
      f("tile_log2", 0, 8, "log2 of the pixels one frame pass may cover (PIXEL_COUNT at most 2^tile_log2)"),
      f("acc_bits", 8, 8, "bits of a pixel channel's fixed-point sum"), f("count_bits", 16, 8, "bits of a pixel's contribution count"))),
    Register("HW_INDICES", 0x018, RO, "index widths", Seq(
      f("query_bits", 0, 8, "query index bits (QUERY_COUNT at most 2^query_bits)"), f("node_bits", 8, 8, "node index bits (NODE_COUNT at most 2^node_bits)"))),
    Register("CONTROL", 0x020, W1P, "control", Seq(f("start", 0, 1, "start a frame pass with the configuration below (ignored while busy); clears done, IRQ_STATUS and ERROR_CAUSE"))),
    Register("STATUS", 0x024, RO, "status", Seq(
      f("busy", 0, 1, "a frame pass is running"), f("done", 1, 1, "the last pass finished: every query ran, every pixel written, nothing outstanding"),
      f("error", 2, 1, "the last pass ended in error: ERROR_CAUSE says why"))),
    Register("IRQ_ENABLE", 0x028, RW, "interrupt enable", Seq(f("done", 0, 1, "raise the interrupt line when a pass ends (done or error)"))),
    Register("IRQ_STATUS", 0x02c, W1C, "interrupt status: the line is IRQ_STATUS.done and IRQ_ENABLE.done", Seq(f("done", 0, 1, "a pass ended since this bit was cleared"))),
    Register("ERROR_CAUSE", 0x030, RO, "why the last pass ended in error: one bit per cause (table below)"),
    Register("NODE_BASE", 0x040, RW, "byte address of KD node record 0", bits = 64),
    Register("PHOTON_BASE", 0x048, RW, "byte address of photon record 0", bits = 64),
    Register("QUERY_BASE", 0x050, RW, "byte address of query record 0", bits = 64),
    Register("STREAM_BASE", 0x058, RW, "byte address of query-stream entry 0 (with QUERY_ORDER.stream)", bits = 64),
    Register("FRAME_BASE", 0x060, RW, "byte address of pixel 0 of the frame buffer", bits = 64),
    Register("RADIUS", 0x068, RW, "kernel radius h (format bits)", bits = 64),
    Register("NODE_COUNT", 0x070, RW, "KD nodes (= photons); 0 is an empty tree"),
    Register("QUERY_COUNT", 0x074, RW, "query records to run (and query-stream entries, with QUERY_ORDER.stream)"),
    Register("PIXEL_BASE", 0x078, RW, "the first pixel of this pass: every query's pixel lies in PIXEL_BASE .. PIXEL_BASE + PIXEL_COUNT - 1"),
    Register("PIXEL_COUNT", 0x07c, RW, "pixels of this pass, written at the end of the pass"),
    Register("FRAME_SCALE", 0x080, RW, "the frame accumulator's scale: a sum's least significant bit weighs 2^FRAME_SCALE (two's complement)"),
    Register("QUERY_ORDER", 0x084, RW, "where the order of the queries comes from", Seq(f("stream", 0, 1,
      "1: run the QUERY_COUNT entries of the query stream at STREAM_BASE, in stream order; 0: run query records 0 .. QUERY_COUNT - 1 in array order, reading no stream (STREAM_BASE unused)")))
  ) ++ CounterSet.Names.zipWithIndex.map { case (n, k) =>
    Register("CNT_" + n.toUpperCase, CounterBase + 8 * k, RO, s"counter $n (${CounterSet.Units(n)}); reading the low word latches the high word", bits = 64)
  }

  require(registers.flatMap(r => (0 until r.words).map(r.offset + 4 * _)).distinct.size == registers.map(_.words).sum, "registers overlap")
  require(registers.forall(r => r.offset + 4 * r.words <= SpaceBytes), "a register lies beyond the register space")

  private val byName = registers.map(r => r.name -> r).toMap
  def apply(name: String): Register = byName.getOrElse(name, throw new NoSuchElementException(s"no register $name"))

  /** The causes of ERROR_CAUSE: the accumulation's faults ([[FrameAccum.Faults]]) at their bits,
    * then the configuration's and the system's. */
  val causes: Seq[ErrorCause] = FrameAccum.Faults.map(x => ErrorCause(x.bit, x.toString.toUpperCase, x.reason)) ++ Seq(
    ErrorCause(3, "ALIGN", "an array base is not a multiple of 64 bytes"),
    ErrorCause(4, "OVERLAP", "two of the node, photon, query, stream (if read) and frame arrays overlap"),
    ErrorCause(5, "EMPTY", "QUERY_COUNT or PIXEL_COUNT is zero"),
    ErrorCause(6, "LIMIT", "a count exceeds the hardware: NODE_COUNT, QUERY_COUNT or PIXEL_COUNT beyond HW_INDICES and HW_FRAME, or an array beyond the address width"),
    ErrorCause(7, "PIXEL", "a query's pixel lies outside PIXEL_BASE .. PIXEL_BASE + PIXEL_COUNT - 1"),
    ErrorCause(8, "QUERY", "a stream entry's query index is not below QUERY_COUNT"),
    ErrorCause(9, "RECORD", "the MAPM refused a record or a response: a malformed node or query record, an invalid tree-search input, a read beat its caches were not waiting for"),
    ErrorCause(10, "AXI_READ", "a read came back with an error response (SLVERR or DECERR)"),
    ErrorCause(11, "AXI_WRITE", "a write came back with an error response (SLVERR or DECERR)"),
    ErrorCause(12, "AXI_PROTOCOL", "the memory side broke an AXI4 rule (a response to nothing outstanding, a wrong RLAST, a payload changed or a valid dropped before its handshake)"))
  require(causes.map(_.bit) == causes.indices, "error causes take bits 0, 1, 2, ... in order")

  def cause(name: String): ErrorCause = causes.find(_.name == name).getOrElse(throw new NoSuchElementException(s"no error cause $name"))

  /** The register table, the error causes and the access types as Markdown (docs/coprocessor.md). */
  def markdown: String = {
    def hex(v: Int) = f"0x$v%03x"
    val regs = registers.filterNot(_.name.startsWith("CNT_")).map { r =>
      val where = if (r.words == 2) s"${hex(r.offset)} (LO), ${hex(r.offset + 4)} (HI)" else hex(r.offset)
      val fields = if (r.fields.isEmpty) (if (r.words == 2) "64-bit value" else "32-bit value")
        else r.fields.map(x => s"`${x.name}` [${if (x.width == 1) x.lsb.toString else s"${x.lsb + x.width - 1}:${x.lsb}"}]: ${x.doc}").mkString("; ")
      s"| $where | `${r.name}` | ${r.access.name} | ${r.doc} | $fields |"
    }
    val counters = CounterSet.Names.zipWithIndex.map { case (n, k) =>
      s"| ${hex(CounterBase + 8 * k)} | `CNT_${n.toUpperCase}` | `$n` | ${CounterSet.Units(n)} |"
    }
    (Seq(s"Register map version $Version, ${SpaceBytes / 1024} KiB of AXI4-Lite space, 32-bit words, little-endian.", "",
      "| offset | register | access | meaning | fields |", "|---|---|---|---|---|") ++ regs ++
      Seq("", s"Counters: 64 bits each, low word first; reading the low word latches the high word.", "",
        "| offset | register | counter | unit |", "|---|---|---|---|") ++ counters ++
      Seq("", "`ERROR_CAUSE` bits:", "", "| bit | name | reason |", "|---|---|---|") ++
      causes.map(c => s"| ${c.bit} | `${c.name}` | ${c.reason} |") ++
      Seq("", "Access: " + Seq(RO, RW, W1P, W1C).map(a => s"${a.name}: ${a.doc}").mkString("; ") + ".")).mkString("\n") + "\n"
  }

  /** `mapm_regs.h`: offsets, field shifts and masks, the error causes with their reasons, the
    * counters' names. Plain C99 (the driver is C; the harness includes it from C++). */
  def cHeader: String = {
    def hex(v: Long) = "0x" + v.toHexString + "u"
    val regs = registers.flatMap { r =>
      val p = s"MAPM_REG_${r.name}"
      val offs = if (r.words == 2) Seq(s"#define ${p}_LO ${hex(r.offset)}", s"#define ${p}_HI ${hex(r.offset + 4)}") else Seq(s"#define $p ${hex(r.offset)}")
      offs ++ r.fields.flatMap { x =>
        val q = s"MAPM_${r.name}_${x.name.toUpperCase}"
        Seq(s"#define ${q}_SHIFT ${x.lsb}u", s"#define ${q}_MASK ${hex(x.mask)}")
      }
    }
    val causes = this.causes.map(c => s"#define MAPM_ERR_${c.name} (1u << ${c.bit})")
    val reason = this.causes.map(c => s"    case ${c.bit}: return \"${c.reason}\";")
    val counterNames = CounterSet.Names.zipWithIndex.map { case (n, k) => s"    case $k: return \"$n\";" }
    val counterUnits = CounterSet.Names.zipWithIndex.map { case (n, k) => s"    case $k: return \"${CounterSet.Units(n)}\";" }
    (Seq("/* Generated by mapm.format.RegisterMap: do not edit. The MAPM coprocessor's registers (docs/coprocessor.md). */",
      "#ifndef MAPM_REGS_H", "#define MAPM_REGS_H",
      s"#define MAPM_ID_MAGIC ${hex(Magic)}", s"#define MAPM_REGMAP_VERSION ${Version}u", s"#define MAPM_REG_SPACE_BYTES ${SpaceBytes}u",
      s"#define MAPM_COUNTER_BASE ${hex(CounterBase)}", s"#define MAPM_COUNTER_COUNT ${CounterSet.Names.size}u",
      s"#define MAPM_ERROR_CAUSES ${this.causes.size}u") ++ regs ++ causes ++
      Seq("/* The reason of ERROR_CAUSE bit `bit`, or 0. */", "static inline const char* mapm_error_reason(unsigned bit) {", "  switch (bit) {") ++
      reason ++ Seq("    default: return 0;", "  }", "}",
        "/* The name and unit of counter k, or 0. */", "static inline const char* mapm_counter_name(unsigned k) {", "  switch (k) {") ++
      counterNames ++ Seq("    default: return 0;", "  }", "}", "static inline const char* mapm_counter_unit(unsigned k) {", "  switch (k) {") ++
      counterUnits ++ Seq("    default: return 0;", "  }", "}", "#endif")).mkString("", "\n", "\n")
  }
}
