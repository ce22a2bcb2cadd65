package mapm.format

import mapm.MapmError
import mapm.model.FloatFormat

/** The records of the memory image the MAPM reads (docs/memory-layout.md), defined once: the
  * image writer and reader ([[mapm.format.MemoryImage]]), the hardware's record bundles and
  * addresses, and the harness's generated header all take sizes and offsets from here.
  *
  * Format values sit in slots of `slot` bytes (the value's bits zero-extended): 4 bytes for
  * formats up to 32 bits, or 2 bytes (the packed layout) for formats up to 16 bits.
  */
object MemoryLayout {
  /** Every array of the image starts at a multiple of this many bytes (the L2 line size). */
  val Alignment = 64
  val Magic = "MAPMIMG1"
  val Version = 1

  /** The 64-byte image header. */
  val header: Record = Record("image", 64, Seq(
    Field("magic", 0, 8), Field("version", 8, 2), Field("exp_width", 10, 1), Field("man_width", 11, 1),
    Field("packed", 12, 1), Field("slot", 13, 1), Field("nodes", 16, 4), Field("queries", 20, 4),
    Field("stream_entries", 24, 4), Field("h", 28, 4), Field("photon_base", 32, 8), Field("query_base", 40, 8),
    Field("stream_base", 48, 8), Field("total_bytes", 56, 8)))

  /** A KD node record: the split value in a 4-byte slot in every layout, and the node word
    * ([[mapm.model.NodeWord]]). The node array starts right after the header. */
  val node: Record = Record("node", 8, Seq(Field("split", 0, 4), Field("word", 4, 4)))

  /** Photon record fields, in record order. */
  val PhotonFields: Seq[String] = Seq("x", "y", "z", "power_r", "power_g", "power_b", "kernel", "brdf")

  /** A photon record: eight slots. */
  def photon(slot: Int): Record = Record("photon", 8 * slot, Record.run(PhotonFields, 0, slot))

  /** A query record: the contribution (the part the hardware reads, `queryHwBytes`), then the
    * position and the pixel index for the host. */
  def query(slot: Int): Record = slot match {
    case 4 => Record("query", 32, Record.run(Seq("contrib_r", "contrib_g", "contrib_b"), 0, 4) ++
      Record.run(Seq("x", "y", "z"), 16, 4) :+ Field("pixel", 28, 4))
    case 2 => Record("query", 16, Record.run(Seq("contrib_r", "contrib_g", "contrib_b"), 0, 2) ++
      Record.run(Seq("x", "y", "z"), 6, 2) :+ Field("pixel", 12, 4))
    case s => MapmError.fail(s"memory layout: no query record for $s-byte slots")
  }

  /** Bytes at the start of a query record that the hardware reads (its SOQ cache word): the
    * contribution and, unpacked, the zero word after it. */
  def queryHwBytes(slot: Int): Int = 16

  /** A query-stream entry: the position the host feeds with the query, and its index. */
  def stream(slot: Int): Record = Record("stream", 16, Record.run(Seq("x", "y", "z"), 0, slot) :+ Field("query", 12, 4))

  /** Slot size in bytes for `format`; a [[MapmError]] for formats the records cannot hold. */
  def slotBytes(format: FloatFormat, packed: Boolean): Int = {
    MapmError.check(format.width <= 32,
      s"memory image: format $format is ${format.width} bits wide; records hold formats of at most 32 bits")
    if (packed) {
      MapmError.check(format.width <= 16,
        s"memory image: the packed layout needs a format of at most 16 bits; $format is ${format.width} bits wide")
      2
    } else 4
  }

  /** `a` rounded up to the next multiple of [[Alignment]]. */
  def align(a: Long): Long = (a + Alignment - 1) / Alignment * Alignment
}
