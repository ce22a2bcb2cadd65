package mapm.format

import java.nio.ByteBuffer

import mapm.MapmError

/** One field of a fixed-layout, little-endian binary record: its byte offset and size (1, 2, 4 or
  * 8 bytes, read as an unsigned integer). */
final case class Field(name: String, offset: Int, bytes: Int) {
  require(Set(1, 2, 4, 8)(bytes), s"field $name: size must be 1, 2, 4 or 8 bytes, got $bytes")
  require(offset >= 0 && offset % bytes == 0, s"field $name: offset $offset is not a multiple of its size $bytes")
  def end: Int = offset + bytes
}

/** A fixed-size, little-endian binary record: the one definition of a file or memory record. The
  * Scala writers and readers get and put fields through it, the hardware derives its record sizes
  * and field positions from it, and [[CHeader]] turns it into the C++ reader's constants and
  * accessors. Bytes outside every field are zero.
  *
  * @param name   a C identifier prefix for the generated header (e.g. `node`)
  * @param bytes  the record size
  * @param fields the fields, in offset order, not overlapping
  */
final case class Record(name: String, bytes: Int, fields: Seq[Field]) {
  require(name.matches("[a-z][a-z0-9_]*"), s"record name $name must be a lower-case C identifier")
  require(fields.map(_.name).distinct.size == fields.size, s"record $name: duplicate field names")
  require(fields.zip(fields.drop(1)).forall { case (a, b) => a.end <= b.offset }, s"record $name: fields overlap or are out of order")
  require(fields.forall(_.end <= bytes), s"record $name: a field ends beyond the record's $bytes bytes")

  private val byName: Map[String, Field] = fields.map(f => f.name -> f).toMap

  /** The field called `n`. */
  def apply(n: String): Field = byName.getOrElse(n, throw new NoSuchElementException(s"record $name has no field $n"))

  /** Field `f` of the record at byte `base` of `b` (a little-endian buffer), as an unsigned value
    * (8-byte fields as the raw 64 bits). */
  def get(b: ByteBuffer, base: Long, f: String): Long = get(b, base, apply(f))

  /** Field `fd` (one of this record's, looked up once by a caller in a loop) of the record at
    * byte `base` of `b`. */
  def get(b: ByteBuffer, base: Long, fd: Field): Long = {
    val at = Record.index(base + fd.offset)
    fd.bytes match {
      case 1 => b.get(at).toLong & 0xffL
      case 2 => b.getShort(at).toLong & 0xffffL
      case 4 => b.getInt(at).toLong & 0xffffffffL
      case _ => b.getLong(at)
    }
  }

  /** Writes `v` (its low bytes) into field `f` of the record at byte `base` of `b`. */
  def put(b: ByteBuffer, base: Long, f: String, v: Long): Unit = put(b, base, apply(f), v)

  /** Writes `v` into field `fd` (one of this record's) of the record at byte `base` of `b`. */
  def put(b: ByteBuffer, base: Long, fd: Field, v: Long): Unit = {
    val at = Record.index(base + fd.offset)
    fd.bytes match {
      case 1 => b.put(at, v.toByte)
      case 2 => b.putShort(at, v.toShort)
      case 4 => b.putInt(at, v.toInt)
      case _ => b.putLong(at, v)
    }
  }
}

object Record {
  private def index(at: Long): Int = {
    MapmError.check(at >= 0 && at <= Int.MaxValue, s"record offset $at is beyond what one buffer holds")
    at.toInt
  }

  /** An 8-character ASCII magic as the little-endian u64 an 8-byte field holds. */
  def magic(s: String): Long = {
    MapmError.check(s.length == 8 && s.forall(c => c >= ' ' && c < 127), s"magic $s must be 8 printable ASCII characters")
    s.reverse.foldLeft(0L)((v, c) => v << 8 | c.toLong)
  }

  /** Fields of `bytes` each, one after another from `offset`, named `names`. */
  def run(names: Seq[String], offset: Int, bytes: Int): Seq[Field] =
    names.zipWithIndex.map { case (n, i) => Field(n, offset + i * bytes, bytes) }
}
