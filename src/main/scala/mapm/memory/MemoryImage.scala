package mapm.memory

import java.nio.{ByteBuffer, ByteOrder}

import mapm.MapmError
import mapm.model.{FloatFormat, NodeWord, PhotonMap, QuerySet}

/** The binary memory image the MAPM hardware reads (docs/memory-layout.md): a 64-byte header, the
  * KD node array, the photon array, the query array and the query stream, each starting at a
  * multiple of 64 bytes. Little-endian throughout.
  *
  * Format values sit in slots: 4 bytes each (the value's bits zero-extended) for formats up to 32
  * bits wide; with `packed`, 2-byte slots for formats up to 16 bits wide, which halves the photon
  * and query records. Node records and the stream are the same in both layouts.
  *
  * Record layouts (byte offsets; s = slot size):
  *  - node (8 B): 0 split value (4-byte slot), 4 [[NodeWord]] (axis, child flags, right index)
  *  - photon (8 s B): x, y, z, power r, g, b, kernel, BRDF at 0, s, ..., 7 s
  *  - query, unpacked (32 B): contribution r, g, b at 0, 4, 8; 12 zero; position x, y, z at
  *    16, 20, 24; pixel index (u32) 28 (the hardware reads the first 16 bytes, the host the rest)
  *  - query, packed (16 B): contribution r, g, b at 0, 2, 4; position x, y, z at 6, 8, 10; pixel 12
  *  - stream (16 B): position x, y, z at 0, s, 2 s; query index (u32) at 12; the rest zero
  *
  * Fields are held as arrays indexed by node (photon fields in node order) or query.
  */
final class MemoryImage(
    val format: FloatFormat,
    val packed: Boolean,
    val h: Long,
    val nodeSplit: Array[Long],
    val nodeWord: Array[Int],
    /** photon(f)(i): field f of node i's photon, f in [[MemoryImage.PhotonFields]] order */
    val photon: Array[Array[Long]],
    /** contribution(c)(q) for channel c of query q */
    val contribution: Array[Array[Long]],
    val pixel: Array[Int],
    /** position(a)(q) for axis a of query q */
    val position: Array[Array[Long]],
    /** the query stream in issue order: query index per entry (its position comes from `position`) */
    val stream: Array[Int]
) {
  import MemoryImage._

  val nodeCount: Int = nodeWord.length
  val queryCount: Int = pixel.length
  val slot: Int = slotBytes(format, packed)
  val photonBytes: Int = 8 * slot
  val queryBytes: Int = if (packed) 16 else 32
  val nodeBase: Long = HeaderBytes
  val photonBase: Long = align(nodeBase + NodeBytes.toLong * nodeCount)
  val queryBase: Long = align(photonBase + photonBytes.toLong * nodeCount)
  val streamBase: Long = align(queryBase + queryBytes.toLong * queryCount)
  val totalBytes: Long = streamBase + StreamBytes.toLong * stream.length

  /** The image as bytes. */
  def toBytes: Array[Byte] = {
    MapmError.check(totalBytes <= Int.MaxValue, s"memory image of $totalBytes bytes is too large to build in memory")
    val b = ByteBuffer.allocate(totalBytes.toInt).order(ByteOrder.LITTLE_ENDIAN)
    b.put(Magic)
    b.putShort(8, Version.toShort)
    b.put(10, format.expWidth.toByte); b.put(11, format.manWidth.toByte)
    b.put(12, (if (packed) 1 else 0).toByte); b.put(13, slot.toByte)
    b.putInt(16, nodeCount); b.putInt(20, queryCount); b.putInt(24, stream.length); b.putInt(28, h.toInt)
    b.putLong(32, photonBase); b.putLong(40, queryBase); b.putLong(48, streamBase); b.putLong(56, totalBytes)
    def putSlot(at: Long, v: Long): Unit =
      if (slot == 4) b.putInt(at.toInt, v.toInt) else b.putShort(at.toInt, v.toShort)
    for (i <- 0 until nodeCount) {
      val at = (nodeBase + NodeBytes.toLong * i).toInt
      b.putInt(at, nodeSplit(i).toInt); b.putInt(at + 4, nodeWord(i))
    }
    for (i <- 0 until nodeCount; f <- 0 until 8) putSlot(photonBase + photonBytes.toLong * i + f * slot, photon(f)(i))
    for (q <- 0 until queryCount) {
      val at = queryBase + queryBytes.toLong * q
      val (cOff, pixOff, posOff) = queryOffsets(packed)
      for (c <- 0 until 3) putSlot(at + cOff + c * slot, contribution(c)(q))
      b.putInt((at + pixOff).toInt, pixel(q))
      for (a <- 0 until 3) putSlot(at + posOff + a * slot, position(a)(q))
    }
    for ((q, k) <- stream.zipWithIndex) {
      val at = streamBase + StreamBytes.toLong * k
      for (a <- 0 until 3) putSlot(at + a * slot, position(a)(q))
      b.putInt((at + 12).toInt, q)
    }
    b.array()
  }

  def write(path: java.nio.file.Path): Unit =
    try java.nio.file.Files.write(path, toBytes)
    catch { case e: java.io.IOException => MapmError.fail(s"cannot write memory image $path: $e") }

  override def equals(o: Any): Boolean = o match {
    case m: MemoryImage =>
      format == m.format && packed == m.packed && h == m.h &&
        java.util.Arrays.equals(nodeSplit, m.nodeSplit) && java.util.Arrays.equals(nodeWord, m.nodeWord) &&
        java.util.Arrays.deepEquals(photon.asInstanceOf[Array[AnyRef]], m.photon.asInstanceOf[Array[AnyRef]]) &&
        java.util.Arrays.deepEquals(contribution.asInstanceOf[Array[AnyRef]], m.contribution.asInstanceOf[Array[AnyRef]]) &&
        java.util.Arrays.equals(pixel, m.pixel) &&
        java.util.Arrays.deepEquals(position.asInstanceOf[Array[AnyRef]], m.position.asInstanceOf[Array[AnyRef]]) &&
        java.util.Arrays.equals(stream, m.stream)
    case _ => false
  }
  override def hashCode: Int = (format, packed, h, nodeCount, queryCount, java.util.Arrays.hashCode(nodeWord)).hashCode
}

object MemoryImage {
  val Magic: Array[Byte] = "MAPMIMG1".getBytes("US-ASCII")
  val Version = 1
  val HeaderBytes = 64
  val NodeBytes = 8
  val StreamBytes = 16
  /** Every array starts at a multiple of this many bytes. */
  val Alignment = 64
  /** Photon record fields, in record order. */
  val PhotonFields: Seq[String] = Seq("x", "y", "z", "power r", "power g", "power b", "kernel", "BRDF")

  def align(a: Long): Long = (a + Alignment - 1) / Alignment * Alignment

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

  /** Byte offsets of contribution, pixel index and position within a query record. */
  private def queryOffsets(packed: Boolean): (Int, Int, Int) = if (packed) (0, 12, 6) else (0, 28, 16)

  /** The image of a photon map and its queries; the stream issues the queries in `order`
    * (default: query order). */
  def from(map: PhotonMap, queries: QuerySet, packed: Boolean = false, order: Option[Array[Int]] = None): MemoryImage = {
    MapmError.check(map.format == queries.format, s"memory image: photon map (${map.format}) and queries (${queries.format}) use different formats")
    slotBytes(map.format, packed)
    val stream = order.getOrElse(Array.tabulate(queries.size)(identity))
    MapmError.check(stream.sorted.sameElements(0 until queries.size), "memory image: the stream order must be a permutation of the queries")
    new MemoryImage(map.format, packed, map.h, map.split.clone(), NodeWord.all(map.tree),
      Array(map.px, map.py, map.pz, map.power(0), map.power(1), map.power(2), map.kernel, map.brdf).map(_.clone()),
      queries.contribution.map(_.clone()), queries.pixel.clone(), Array(queries.qx, queries.qy, queries.qz).map(_.clone()), stream.clone())
  }

  def read(path: java.nio.file.Path): MemoryImage = {
    val bytes =
      try java.nio.file.Files.readAllBytes(path)
      catch { case e: java.io.IOException => MapmError.fail(s"cannot read memory image $path: $e") }
    fromBytes(bytes, path.toString)
  }

  /** Parses an image; any inconsistency is a [[MapmError]] naming `name`. */
  def fromBytes(bytes: Array[Byte], name: String = "memory image"): MemoryImage = {
    def bad(what: String): Nothing = MapmError.fail(s"$name: $what")
    if (bytes.length < HeaderBytes) bad(s"${bytes.length} bytes is shorter than the $HeaderBytes-byte header")
    val b = ByteBuffer.wrap(bytes).order(ByteOrder.LITTLE_ENDIAN)
    if (!bytes.take(8).sameElements(Magic)) bad("not a MAPM memory image (bad magic)")
    val version = b.getShort(8) & 0xffff
    if (version != Version) bad(s"version $version, expected $Version")
    val (ew, mw) = (b.get(10).toInt, b.get(11).toInt)
    if (ew < 2 || ew > 11 || mw < 1 || mw > 52) bad(s"invalid format e${ew}m$mw")
    val format = FloatFormat(ew, mw)
    val packed = b.get(12) match { case 0 => false; case 1 => true; case v => bad(s"packed flag $v is not 0 or 1") }
    val slot = try slotBytes(format, packed) catch { case e: MapmError => bad(e.getMessage) }
    if (b.get(13) != slot) bad(s"slot size ${b.get(13)} does not match format $format (${slot})")
    val (n, nq, ns) = (b.getInt(16), b.getInt(20), b.getInt(24))
    if (n < 0 || nq < 0 || ns != nq) bad(s"inconsistent counts: $n nodes, $nq queries, $ns stream entries")
    val h = b.getInt(28).toLong & format.mask
    val shape = new MemoryImage(format, packed, h, new Array[Long](n), new Array[Int](n), Array.fill(8)(new Array[Long](n)),
      Array.fill(3)(new Array[Long](nq)), new Array[Int](nq), Array.fill(3)(new Array[Long](nq)), new Array[Int](nq))
    for ((got, want, what) <- Seq((b.getLong(32), shape.photonBase, "photon"), (b.getLong(40), shape.queryBase, "query"),
                                  (b.getLong(48), shape.streamBase, "stream"), (b.getLong(56), shape.totalBytes, "total size")))
      if (got != want) bad(s"$what offset $got, expected $want for $n nodes and $nq queries")
    if (bytes.length != shape.totalBytes) bad(s"${bytes.length} bytes, the header says ${shape.totalBytes}")
    val mask = format.mask
    def slotAt(at: Long): Long = (if (slot == 4) b.getInt(at.toInt).toLong else b.getShort(at.toInt).toLong) & mask
    for (i <- 0 until n) {
      val at = shape.nodeBase + NodeBytes.toLong * i
      shape.nodeSplit(i) = b.getInt(at.toInt).toLong & mask
      val w = b.getInt(at.toInt + 4)
      if (NodeWord.axis(w) > 2) bad(s"node $i has axis field 3")
      if ((w & NodeWord.HasRight) != 0 && (NodeWord.right(w) <= i || NodeWord.right(w) >= n)) bad(s"node $i has right child ${NodeWord.right(w)} outside ${i + 1}..${n - 1}")
      if ((w & NodeWord.HasLeft) != 0 && i + 1 >= n) bad(s"node $i has a left child beyond the last node")
      shape.nodeWord(i) = w
      for (f <- 0 until 8) shape.photon(f)(i) = slotAt(shape.photonBase + shape.photonBytes.toLong * i + f * slot)
    }
    val (cOff, pixOff, posOff) = queryOffsets(packed)
    for (q <- 0 until nq) {
      val at = shape.queryBase + shape.queryBytes.toLong * q
      for (c <- 0 until 3) shape.contribution(c)(q) = slotAt(at + cOff + c * slot)
      shape.pixel(q) = b.getInt((at + pixOff).toInt)
      for (a <- 0 until 3) shape.position(a)(q) = slotAt(at + posOff + a * slot)
    }
    for (k <- 0 until nq) {
      val at = shape.streamBase + StreamBytes.toLong * k
      val q = b.getInt((at + 12).toInt)
      if (q < 0 || q >= nq) bad(s"stream entry $k names query $q outside 0..${nq - 1}")
      for (a <- 0 until 3)
        if (slotAt(at + a * slot) != shape.position(a)(q)) bad(s"stream entry $k: position differs from query $q's record")
      shape.stream(k) = q
    }
    shape
  }
}
