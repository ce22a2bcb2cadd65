package mapm.format

import java.nio.{ByteBuffer, ByteOrder}
import java.nio.file.{Files, Path}

import mapm.MapmError
import mapm.numerics.FloatFormat

/** The expected-SO file (docs/harness.md): the shader operations the MAPM must report for a
  * frame, as [[mapm.sim.ExpectedSo]] computes them and the harness (tools/harness/expected.h,
  * through the generated `mapm_formats.h`) checks them. Little-endian: the [[header]], then one
  * [[record]] per SO sorted by (query, photon).
  */
object ExpectedSoFile {
  val Magic = "MAPMSO01"
  val Version = 2

  /** The 32-byte header: magic, version, the format and its colour field size, the record count
    * and the image size. */
  val header: Record = Record("expected", 32, Seq(
    Field("magic", 0, 8), Field("version", 8, 4), Field("exp_width", 12, 1), Field("man_width", 13, 1),
    Field("colour_bytes", 14, 1), Field("count", 16, 8), Field("width", 24, 4), Field("height", 28, 4)))

  /** Bytes of each colour field for `format`: 4 up to 32 bits, 8 above. */
  def colourBytes(format: FloatFormat): Int = if (format.width <= 32) 4 else 8

  /** One SO: query, photon, colour bits per channel in `colourBytes` bytes each, and the flags
    * word ([[FlagBits]] bits of flags per channel, then cond at bit [[CondBit]]). 24 bytes with
    * 4-byte colours, 40 with 8-byte ones. */
  def record(colourBytes: Int): Record = {
    MapmError.check(colourBytes == 4 || colourBytes == 8, s"expected SOs: colour fields are 4 or 8 bytes, not $colourBytes")
    val flags = 8 + 3 * colourBytes
    Record("so", (flags + 2 + 7) / 8 * 8, Seq(Field("query", 0, 4), Field("photon", 4, 4)) ++
      Record.run(Seq("colour_r", "colour_g", "colour_b"), 8, colourBytes) :+ Field("flags", flags, 2))
  }

  /** Bits of each channel's flags in the flags word (channel c at 3 c). */
  val FlagBits = 3
  /** The cond bit of the flags word. */
  val CondBit = 9

  /** One SO as the file holds it. */
  final case class Row(query: Int, photon: Int, colour: Seq[Long], flags: Seq[Int], cond: Boolean)

  /** A whole file: the format, the image size and the rows in file order. */
  final case class Contents(format: FloatFormat, width: Int, height: Int, rows: IndexedSeq[Row])

  /** The records of a file in `format`, with their fields looked up once: writes and reads one SO
    * at a byte offset of a little-endian buffer. */
  final class Codec(val format: FloatFormat) {
    val record: Record = ExpectedSoFile.record(colourBytes(format))
    private val queryF = record("query")
    private val photonF = record("photon")
    private val colourF = IndexedSeq("colour_r", "colour_g", "colour_b").map(record(_))
    private val flagsF = record("flags")

    /** Writes the record of one SO at byte `at` of `b`: colour bits `colour(c)`, the flags word `flags`. */
    def put(b: ByteBuffer, at: Int, query: Int, photon: Int, colour: Array[Long], flags: Int): Unit = {
      record.put(b, at, queryF, query.toLong)
      record.put(b, at, photonF, photon.toLong)
      for (c <- 0 until 3) record.put(b, at, colourF(c), colour(c))
      record.put(b, at, flagsF, flags.toLong)
    }

    /** Whether the record at byte `at` of `b` has cond set. */
    def cond(b: ByteBuffer, at: Int): Boolean = (record.get(b, at, flagsF) >> CondBit & 1) != 0

    /** The query of the record at byte `at` of `b`. */
    def query(b: ByteBuffer, at: Int): Int = record.get(b, at, queryF).toInt

    /** Channel `c`'s colour bits of the record at byte `at` of `b`. */
    def colour(b: ByteBuffer, at: Int, c: Int): Long = record.get(b, at, colourF(c))

    /** The row of the record at byte `at` of `b`. */
    def row(b: ByteBuffer, at: Int): Row = {
      val fl = record.get(b, at, flagsF).toInt
      Row(query(b, at), record.get(b, at, photonF).toInt, (0 until 3).map(colour(b, at, _)),
        (0 until 3).map(c => fl >> (FlagBits * c) & ((1 << FlagBits) - 1)), cond(b, at))
    }
  }

  /** The header of a file of `count` records for a `width` x `height` image. */
  def headerBytes(format: FloatFormat, count: Long, width: Int, height: Int): Array[Byte] = {
    val b = ByteBuffer.allocate(header.bytes).order(ByteOrder.LITTLE_ENDIAN)
    for ((f, v) <- Seq("magic" -> Record.magic(Magic), "version" -> Version.toLong, "exp_width" -> format.expWidth.toLong,
                       "man_width" -> format.manWidth.toLong, "colour_bytes" -> colourBytes(format).toLong, "count" -> count,
                       "width" -> width.toLong, "height" -> height.toLong))
      header.put(b, 0, f, v)
    b.array()
  }

  /** The flags word of channel flags `flags` and `cond`. */
  def flagsWord(flags: Seq[Int], cond: Boolean): Int =
    flags.zipWithIndex.map { case (f, c) => f << (FlagBits * c) }.sum | (if (cond) 1 << CondBit else 0)

  /** Writes `rows` (sorted here by (query, photon)) as a file for a `width` x `height` image. */
  def write(path: Path, format: FloatFormat, width: Int, height: Int, rows: Seq[Row]): Unit = {
    val codec = new Codec(format)
    val b = ByteBuffer.allocate(header.bytes + codec.record.bytes * rows.size).order(ByteOrder.LITTLE_ENDIAN)
    b.put(headerBytes(format, rows.size.toLong, width, height))
    for ((r, i) <- rows.sortBy(r => (r.query, r.photon)).zipWithIndex)
      codec.put(b, header.bytes + codec.record.bytes * i, r.query, r.photon, r.colour.toArray, flagsWord(r.flags, r.cond))
    try Files.write(path, b.array())
    catch { case e: java.io.IOException => MapmError.fail(s"cannot write expected SOs $path: ${e.getMessage}") }
  }

  /** Reads a whole file; a [[MapmError]] naming `path` if it is not one. */
  def read(path: Path): Contents = {
    val bytes =
      try Files.readAllBytes(path)
      catch { case e: java.io.IOException => MapmError.fail(s"cannot read expected SOs $path: ${e.getMessage}") }
    def bad(what: String): Nothing = MapmError.fail(s"$path: $what")
    if (bytes.length < header.bytes) bad(s"${bytes.length} bytes is shorter than the ${header.bytes}-byte header")
    val b = ByteBuffer.wrap(bytes).order(ByteOrder.LITTLE_ENDIAN)
    def field(f: String): Long = header.get(b, 0, f)
    if (field("magic") != Record.magic(Magic)) bad("not an expected-SO file (bad magic)")
    if (field("version") != Version) bad(s"version ${field("version")}, expected $Version")
    val (ew, mw) = (field("exp_width").toInt, field("man_width").toInt)
    if (ew < 2 || ew > 11 || mw < 1 || mw > 52) bad(s"invalid format e${ew}m$mw")
    val format = FloatFormat(ew, mw)
    if (field("colour_bytes") != colourBytes(format)) bad(s"colour fields of ${field("colour_bytes")} bytes, expected ${colourBytes(format)} for $format")
    val codec = new Codec(format)
    val count = field("count")
    if (bytes.length != header.bytes + codec.record.bytes * count) bad(s"${bytes.length} bytes, the header says $count records")
    Contents(format, field("width").toInt, field("height").toInt,
      (0 until count.toInt).map(i => codec.row(b, header.bytes + codec.record.bytes * i)))
  }
}
