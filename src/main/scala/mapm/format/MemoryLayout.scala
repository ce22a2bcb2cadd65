package mapm.format

import mapm.MapmError
import mapm.numerics.FloatFormat

/** How format values sit in the image's records: each value in a slot of 2, 4 or 8 bytes (its
  * bits zero-extended), the smallest that holds the format and is at least `minSlot`.
  * [[SlotLayout.Packed]] (the default) packs 16-bit formats into 2-byte slots; [[SlotLayout.Wide]]
  * keeps them in 4-byte slots, so that the two can be compared on one design. */
sealed abstract class SlotLayout(name: String, val code: Int, val minSlot: Int) extends mapm.Choice(name) {
  /** The slot size for `format`. */
  def slotBytes(format: FloatFormat): Int = MemoryLayout.SlotSizes.find(s => s >= minSlot && 8 * s >= format.width).get
}

object SlotLayout extends mapm.Choices[SlotLayout] {
  /** The smallest slot of 2, 4 or 8 bytes: the layout the hardware reads by default. */
  case object Packed extends SlotLayout("packed", 0, 2)
  /** Slots of at least 4 bytes, whatever the format. */
  case object Wide extends SlotLayout("wide", 1, 4)

  val all: Seq[SlotLayout] = Seq(Packed, Wide)

  protected def unknown(text: String): String = s"layout '$text': expected ${all.map(_.name).mkString(" or ")}"

  /** The layout of header code `code`, if any. */
  def ofCode(code: Long): Option[SlotLayout] = all.find(_.code == code)
}

/** The records of the memory image the MAPM reads (docs/memory-layout.md), defined once: the
  * image writer and reader ([[mapm.format.MemoryImage]]), the hardware's record bundles and
  * addresses, and the harness's generated header all take sizes and offsets from here.
  *
  * Format values sit in slots of `slot` bytes ([[SlotSizes]]; [[SlotLayout]] picks one per
  * format). Every record is a power of two of bytes, so an array index shifted left is a record's
  * offset and a cache line holds whole records.
  */
object MemoryLayout {
  /** Every array of the image starts at a multiple of this many bytes (the L2 line size). A cache
    * line of at most this size never reaches past the end of an array's aligned span. */
  val Alignment = 64
  val Magic = "MAPMIMG1"
  val Version = 3
  /** The slot sizes a layout may use, in bytes. */
  val SlotSizes: Seq[Int] = Seq(2, 4, 8)

  /** The 64-byte image header. `h` is the kernel radius, format bits zero-extended to 8 bytes. */
  val header: Record = Record("image", 64, Seq(
    Field("magic", 0, 8), Field("version", 8, 2), Field("exp_width", 10, 1), Field("man_width", 11, 1),
    Field("layout", 12, 1), Field("slot", 13, 1), Field("nodes", 16, 4), Field("queries", 20, 4),
    Field("h", 24, 8), Field("photon_base", 32, 8), Field("query_base", 40, 8),
    Field("stream_base", 48, 8), Field("total_bytes", 56, 8)))

  private def checkSlot(slot: Int): Unit =
    MapmError.check(SlotSizes.contains(slot), s"memory layout: no records for $slot-byte slots (${SlotSizes.mkString(", ")})")

  /** A KD node record: the split value (in at least 4 bytes), then the node word
    * ([[mapm.numerics.NodeWord]]): 8 bytes for slots up to 4 bytes, 16 for 8-byte slots. The node
    * array starts right after the header. */
  def node(slot: Int): Record = {
    checkSlot(slot)
    val split = slot max 4
    Record("node", 2 * split, Seq(Field("split", 0, split), Field("word", split, 4)))
  }

  /** Photon record fields, in record order. */
  val PhotonFields: Seq[String] = Seq("x", "y", "z", "power_r", "power_g", "power_b", "kernel", "brdf")

  /** A photon record: eight slots. */
  def photon(slot: Int): Record = { checkSlot(slot); Record("photon", 8 * slot, Record.run(PhotonFields, 0, slot)) }

  /** A query record: the contribution, the position and the pixel index; the hardware reads all
    * of it (`queryHwBytes`). */
  def query(slot: Int): Record = {
    checkSlot(slot)
    val contrib = Record.run(Seq("contrib_r", "contrib_g", "contrib_b"), 0, slot)
    slot match {
      case 2 => Record("query", 16, contrib ++ Record.run(Seq("x", "y", "z"), 6, 2) :+ Field("pixel", 12, 4))
      case s => Record("query", 8 * s, contrib ++ Record.run(Seq("x", "y", "z"), 4 * s, s) :+ Field("pixel", 7 * s, 4))
    }
  }

  /** Bytes of a query record that the hardware reads (its SOQ cache word): the whole record. */
  def queryHwBytes(slot: Int): Int = query(slot).bytes

  /** A query-stream entry: the index of the query to run (4 bytes whatever the slot; the query's
    * position is in its record). `slot` is checked, so that every record takes one. */
  def stream(slot: Int): Record = { checkSlot(slot); Record("stream", 4, Seq(Field("query", 0, 4))) }

  /** `a` rounded up to the next multiple of [[Alignment]]. */
  def align(a: Long): Long = (a + Alignment - 1) / Alignment * Alignment
}
