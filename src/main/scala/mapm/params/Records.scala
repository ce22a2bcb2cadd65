package mapm.params

import chisel3._
import chisel3.util.{isPow2, log2Ceil}
import mapm.format.{MemoryLayout, Record => Layout}
import mapm.numerics.NodeWord

/** The memory records the hardware reads (docs/memory-layout.md) as Chisel bundles: a cache word
  * is decoded with `.asTypeOf`. Sizes and offsets come from [[mapm.format.MemoryLayout]], the node
  * word's bits from [[mapm.numerics.NodeWord]]; each bundle checks at elaboration that it matches them.
  * Records are little-endian (the field at byte 0 is bits 0 and up) and a bundle's last field is
  * its least significant one, so every bundle declares its fields from the record's end down.
  *
  * @param slot bytes of a format slot ([[MapmParams.slotBytes]]: the format's in the configured
  *             [[mapm.format.SlotLayout]])
  */
final class Records(val slot: Int) {
  /** The node record. */
  val node: Layout = MemoryLayout.node(slot)
  /** The photon record. */
  val photon: Layout = MemoryLayout.photon(slot)
  /** The query record. */
  val query: Layout = MemoryLayout.query(slot)
  /** Bytes of a query record the SOQ cache reads. */
  val queryHwBytes: Int = MemoryLayout.queryHwBytes(slot)
}

object Records {
  /** log2 of a record's size: an array index shifted left by it is the record's byte offset. */
  def indexShift(r: Layout): Int = {
    require(isPow2(r.bytes), s"${r.name} records are ${r.bytes} bytes; an address is an index shift only for a power of two")
    log2Ceil(r.bytes)
  }

  /** Checks that `bundle` is exactly as wide as `bytes` bytes of a record called `name`. */
  private[params] def requireWidth(bundle: Data, name: String, bytes: Int): Unit =
    require(bundle.getWidth == 8 * bytes, s"the $name bundle is ${bundle.getWidth} bits wide, its record ${8 * bytes} (${bytes} bytes)")

  /** Checks that field `f` of `layout` is `bytes` bytes at byte `offset`, as a bundle assumes. */
  private[params] def requireField(layout: Layout, f: String, offset: Int, bytes: Int): Unit = {
    val fd = layout(f)
    require(fd.offset == offset && fd.bytes == bytes,
      s"${layout.name} field $f is ${fd.bytes} bytes at byte ${fd.offset} in the memory layout; the bundle has $bytes at $offset")
  }
}

/** A format value in a record slot of `slotBytes` bytes: the `width` format bits, zero-extended.
  * `pad` (the bits above the value, none when the slot is exactly as wide) must be zero in a
  * well-formed image. */
class FormatSlot(slotBytes: Int, width: Int) extends Bundle {
  require(width >= 1 && width <= 8 * slotBytes, s"a $width-bit format does not fit a $slotBytes-byte slot")
  val pad = UInt((8 * slotBytes - width).W)
  val value = UInt(width.W)
}

/** The node word ([[mapm.numerics.NodeWord]]): split axis (3 invalid), whether each child exists and
  * is a leaf, and the right child's index. */
class NodeWordBits extends Bundle {
  val right = UInt(NodeWord.IndexBits.W)
  val rightIsLeaf = Bool()
  val leftIsLeaf = Bool()
  val hasRight = Bool()
  val hasLeft = Bool()
  val axis = UInt(log2Ceil(NodeWord.AxisMask + 1).W)

  require(NodeWord.AxisMask == (1 << axis.getWidth) - 1 && NodeWord.HasLeft == 1 << axis.getWidth &&
    NodeWord.HasRight == NodeWord.HasLeft << 1 && NodeWord.LeftIsLeaf == NodeWord.HasRight << 1 &&
    NodeWord.RightIsLeaf == NodeWord.LeftIsLeaf << 1 && NodeWord.RightShift == axis.getWidth + 4,
    "the node word bundle's bits differ from mapm.numerics.NodeWord's")
  Records.requireWidth(this, "node word", MemoryLayout.node(4)("word").bytes)
}

/** A KD node record of `slotBytes`-byte slots: the split value in its field, the node word, and
  * `pad` (the bytes after the word, none up to 4-byte slots). `width` is the format's. */
class NodeRecord(slotBytes: Int, width: Int) extends Bundle {
  private val layout = MemoryLayout.node(slotBytes)
  val pad = UInt((8 * (layout.bytes - layout("word").end)).W)
  val word = new NodeWordBits
  val split = new FormatSlot(layout("split").bytes, width)

  Records.requireField(layout, "split", 0, split.getWidth / 8)
  Records.requireField(layout, "word", split.getWidth / 8, word.getWidth / 8)
  Records.requireWidth(this, "node", layout.bytes)
}

/** A photon record of `slotBytes`-byte slots, its fields in [[MemoryLayout.PhotonFields]] order:
  * position x, y, z, power per channel (r, g, b), kernel, BRDF. `width` is the format's. */
class PhotonRecord(slotBytes: Int, width: Int) extends Bundle {
  val brdf = new FormatSlot(slotBytes, width)
  val kernel = new FormatSlot(slotBytes, width)
  val power = Vec(Rgb.Channels, new FormatSlot(slotBytes, width))
  val z = new FormatSlot(slotBytes, width)
  val y = new FormatSlot(slotBytes, width)
  val x = new FormatSlot(slotBytes, width)

  /** The slots in record order. */
  def slots: Seq[FormatSlot] = Seq(x, y, z) ++ power ++ Seq(kernel, brdf)

  private val layout = MemoryLayout.photon(slotBytes)
  require(MemoryLayout.PhotonFields == Seq("x", "y", "z") ++ Rgb.Names.map("power_" + _) ++ Seq("kernel", "brdf"),
    s"the photon bundle's fields differ from MemoryLayout.PhotonFields ${MemoryLayout.PhotonFields.mkString(", ")}")
  for ((f, i) <- MemoryLayout.PhotonFields.zipWithIndex) Records.requireField(layout, f, i * slotBytes, slotBytes)
  Records.requireWidth(this, "photon", layout.bytes)
}

/** A query record as the SOQ cache reads it (the whole record, docs/memory-layout.md): the
  * contribution per channel (r, g, b) and the position (x, y, z) in `slotBytes`-byte slots, the
  * pixel index, and `gap` and `tail`, the unused bytes (zero in a well-formed image). `width` is
  * the format's. */
class QueryRecord(slotBytes: Int, width: Int) extends Bundle {
  private val layout = MemoryLayout.query(slotBytes)
  private val posAt = layout("x").offset
  private val pixelAt = layout("pixel").offset
  val tail = UInt((8 * (layout.bytes - pixelAt - 4)).W)
  val pixel = UInt(32.W)
  val pos = Vec(3, new FormatSlot(slotBytes, width))
  val gap = UInt((8 * (posAt - Rgb.Channels * slotBytes)).W)
  val contrib = Vec(Rgb.Channels, new FormatSlot(slotBytes, width))

  for ((c, i) <- Rgb.Names.zipWithIndex) Records.requireField(layout, "contrib_" + c, i * slotBytes, slotBytes)
  for ((a, i) <- Seq("x", "y", "z").zipWithIndex) Records.requireField(layout, a, posAt + i * slotBytes, slotBytes)
  Records.requireField(layout, "pixel", posAt + 3 * slotBytes, 4)
  Records.requireWidth(this, "query", layout.bytes)
}
