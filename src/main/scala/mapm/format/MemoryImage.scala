package mapm.format

import java.nio.{ByteBuffer, ByteOrder}

import mapm.MapmError
import mapm.numerics.{FloatFormat, NodeWord}

/** The binary memory image the MAPM hardware reads (docs/memory-layout.md): the header, the KD
  * node array, the photon array, the query array and the query stream, each starting at a
  * multiple of [[MemoryLayout.Alignment]] bytes. Every record and offset is [[MemoryLayout]]'s;
  * this class holds the fields as arrays indexed by node (photon fields in node order) or query,
  * and writes and reads them through those records.
  *
  * Format values sit in slots of the size `layout` gives the format (2, 4 or 8 bytes), which
  * sizes the node, photon and query records; a stream entry is a 4-byte query index.
  */
final class MemoryImage(
    val format: FloatFormat,
    val layout: SlotLayout,
    val h: Long,
    val nodeSplit: Array[Long],
    val nodeWord: Array[Int],
    /** photon(f)(i): field f of node i's photon, f in [[MemoryLayout.PhotonFields]] order */
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
  import MemoryLayout.align

  val nodeCount: Int = nodeWord.length
  val queryCount: Int = pixel.length
  val slot: Int = layout.slotBytes(format)
  private val records = new Records(slot)
  val nodeBytes: Int = records.nodeR.bytes
  val photonBytes: Int = records.photonR.bytes
  val queryBytes: Int = records.queryR.bytes
  val nodeBase: Long = MemoryLayout.header.bytes
  val photonBase: Long = align(nodeBase + nodeBytes.toLong * nodeCount)
  val queryBase: Long = align(photonBase + photonBytes.toLong * nodeCount)
  val streamBase: Long = align(queryBase + queryBytes.toLong * queryCount)
  /** The stream array is padded to the alignment too, so that it is read in whole 64-byte lines. */
  val totalBytes: Long = align(streamBase + records.streamR.bytes.toLong * stream.length)

  /** The image as bytes. */
  def toBytes: Array[Byte] = {
    MapmError.check(totalBytes <= Int.MaxValue, s"memory image of $totalBytes bytes is too large to build in memory")
    val b = ByteBuffer.allocate(totalBytes.toInt).order(ByteOrder.LITTLE_ENDIAN)
    val hd = MemoryLayout.header
    for ((f, v) <- Seq("magic" -> Record.magic(MemoryLayout.Magic), "version" -> MemoryLayout.Version.toLong,
                       "exp_width" -> format.expWidth.toLong, "man_width" -> format.manWidth.toLong, "layout" -> layout.code.toLong,
                       "slot" -> slot.toLong, "nodes" -> nodeCount.toLong, "queries" -> queryCount.toLong, "h" -> h, "photon_base" -> photonBase, "query_base" -> queryBase,
                       "stream_base" -> streamBase, "total_bytes" -> totalBytes))
      hd.put(b, 0, f, v)
    import records._
    for (i <- 0 until nodeCount) {
      val at = nodeBase + nodeR.bytes.toLong * i
      nodeR.put(b, at, nodeSplitF, nodeSplit(i)); nodeR.put(b, at, nodeWordF, nodeWord(i).toLong)
      val p = photonBase + photonBytes.toLong * i
      for (f <- 0 until 8) photonR.put(b, p, photonF(f), photon(f)(i))
    }
    for (q <- 0 until queryCount) {
      val at = queryBase + queryBytes.toLong * q
      for (c <- 0 until 3) queryR.put(b, at, contribF(c), contribution(c)(q))
      for (a <- 0 until 3) queryR.put(b, at, queryPosF(a), position(a)(q))
      queryR.put(b, at, pixelF, pixel(q).toLong)
    }
    for ((q, k) <- stream.zipWithIndex) {
      val at = streamBase + streamR.bytes.toLong * k
      streamR.put(b, at, streamQueryF, q.toLong)
    }
    b.array()
  }

  def write(path: java.nio.file.Path): Unit =
    try java.nio.file.Files.write(path, toBytes)
    catch { case e: java.io.IOException => MapmError.fail(s"cannot write memory image $path: $e") }

  override def equals(o: Any): Boolean = o match {
    case m: MemoryImage =>
      format == m.format && layout == m.layout && h == m.h &&
        java.util.Arrays.equals(nodeSplit, m.nodeSplit) && java.util.Arrays.equals(nodeWord, m.nodeWord) &&
        java.util.Arrays.deepEquals(photon.asInstanceOf[Array[AnyRef]], m.photon.asInstanceOf[Array[AnyRef]]) &&
        java.util.Arrays.deepEquals(contribution.asInstanceOf[Array[AnyRef]], m.contribution.asInstanceOf[Array[AnyRef]]) &&
        java.util.Arrays.equals(pixel, m.pixel) &&
        java.util.Arrays.deepEquals(position.asInstanceOf[Array[AnyRef]], m.position.asInstanceOf[Array[AnyRef]]) &&
        java.util.Arrays.equals(stream, m.stream)
    case _ => false
  }
  override def hashCode: Int = (format, layout, h, nodeCount, queryCount, java.util.Arrays.hashCode(nodeWord)).hashCode
}

object MemoryImage {
  /** [[MemoryLayout]]'s records for `slot`-byte slots, with their fields looked up once. */
  private final class Records(slot: Int) {
    val nodeR: Record = MemoryLayout.node(slot)
    val photonR: Record = MemoryLayout.photon(slot)
    val queryR: Record = MemoryLayout.query(slot)
    val streamR: Record = MemoryLayout.stream(slot)
    val nodeSplitF: Field = nodeR("split")
    val nodeWordF: Field = nodeR("word")
    val photonF: IndexedSeq[Field] = MemoryLayout.PhotonFields.map(photonR(_)).toIndexedSeq
    val contribF: IndexedSeq[Field] = IndexedSeq("contrib_r", "contrib_g", "contrib_b").map(queryR(_))
    val queryPosF: IndexedSeq[Field] = IndexedSeq("x", "y", "z").map(queryR(_))
    val pixelF: Field = queryR("pixel")
    val streamQueryF: Field = streamR("query")
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
    val hd = MemoryLayout.header
    if (bytes.length < hd.bytes) bad(s"${bytes.length} bytes is shorter than the ${hd.bytes}-byte header")
    val b = ByteBuffer.wrap(bytes).order(ByteOrder.LITTLE_ENDIAN)
    def field(f: String): Long = hd.get(b, 0, f)
    if (field("magic") != Record.magic(MemoryLayout.Magic)) bad("not a MAPM memory image (bad magic)")
    val version = field("version")
    if (version != MemoryLayout.Version) bad(s"version $version, expected ${MemoryLayout.Version}")
    val (ew, mw) = (field("exp_width").toInt, field("man_width").toInt)
    if (ew < 2 || ew > 11 || mw < 1 || mw > 52) bad(s"invalid format e${ew}m$mw")
    val format = FloatFormat(ew, mw)
    val layout = SlotLayout.ofCode(field("layout")).getOrElse(bad(s"layout code ${field("layout")} is not ${SlotLayout.all.map(_.code).mkString(" or ")}"))
    val slot = layout.slotBytes(format)
    if (field("slot") != slot) bad(s"slot size ${field("slot")} does not match format $format in the $layout layout ($slot)")
    val (n, nq) = (field("nodes"), field("queries"))
    if (n > Int.MaxValue || nq > Int.MaxValue) bad(s"counts out of range: $n nodes, $nq queries")
    val h = field("h") & format.mask
    val shape = new MemoryImage(format, layout, h, new Array[Long](n.toInt), new Array[Int](n.toInt), Array.fill(8)(new Array[Long](n.toInt)),
      Array.fill(3)(new Array[Long](nq.toInt)), new Array[Int](nq.toInt), Array.fill(3)(new Array[Long](nq.toInt)), new Array[Int](nq.toInt))
    for ((f, want, what) <- Seq(("photon_base", shape.photonBase, "photon"), ("query_base", shape.queryBase, "query"),
                                ("stream_base", shape.streamBase, "stream"), ("total_bytes", shape.totalBytes, "total size")))
      if (field(f) != want) bad(s"$what offset ${field(f)}, expected $want for $n nodes and $nq queries")
    if (bytes.length != shape.totalBytes) bad(s"${bytes.length} bytes, the header says ${shape.totalBytes}")
    val r = new Records(slot)
    import r._
    val mask = format.mask
    for (i <- 0 until shape.nodeCount) {
      val at = shape.nodeBase + shape.nodeBytes.toLong * i
      shape.nodeSplit(i) = nodeR.get(b, at, nodeSplitF) & mask
      val w = nodeR.get(b, at, nodeWordF).toInt
      if (NodeWord.axis(w) > 2) bad(s"node $i has axis field 3")
      if ((w & NodeWord.HasRight) != 0 && (NodeWord.right(w) <= i || NodeWord.right(w) >= n)) bad(s"node $i has right child ${NodeWord.right(w)} outside ${i + 1}..${n - 1}")
      if ((w & NodeWord.HasLeft) != 0 && i + 1 >= n) bad(s"node $i has a left child beyond the last node")
      shape.nodeWord(i) = w
      val p = shape.photonBase + shape.photonBytes.toLong * i
      for (f <- 0 until 8) shape.photon(f)(i) = photonR.get(b, p, photonF(f)) & mask
    }
    for (q <- 0 until shape.queryCount) {
      val at = shape.queryBase + shape.queryBytes.toLong * q
      for (c <- 0 until 3) shape.contribution(c)(q) = queryR.get(b, at, contribF(c)) & mask
      shape.pixel(q) = queryR.get(b, at, pixelF).toInt
      for (a <- 0 until 3) shape.position(a)(q) = queryR.get(b, at, queryPosF(a)) & mask
    }
    for (k <- 0 until shape.queryCount) {
      val at = shape.streamBase + streamR.bytes.toLong * k
      val q = streamR.get(b, at, streamQueryF)
      if (q >= nq) bad(s"stream entry $k names query $q outside 0..${nq - 1}")
      shape.stream(k) = q.toInt
    }
    shape
  }
}
