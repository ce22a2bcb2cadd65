package mapm.numerics

import java.nio.file.{Files, Path}
import mapm.MapmError
import scala.jdk.CollectionConverters._

/** The shader-chain vector files (../shared/vectors/README.md, shader-chain.md §8): CSV with the
  * columns `id, kernel, brdf, h, power, contrib, expected, flags, s, m, E[, p1, q, p2, p3]`.
  * Bit patterns are lowercase hex padded to the format's width; s, m, E and the digit strings
  * are empty for special-case rows (rules 1 and 2). The conventional chain's files
  * (../shared/vectors/conventional/README.md) have the first eight columns only.
  */
object ShaderVectors {
  val Header: Seq[String] = Seq("id", "kernel", "brdf", "h", "power", "contrib", "expected", "flags", "s", "m", "E")
  val DigitColumns: Seq[String] = Seq("p1", "q", "p2", "p3")
  /** The columns of the conventional chain's files: inputs, result and flags. */
  val ResultHeader: Seq[String] = Header.take(8)

  /** One row. `line` is the 1-based line in the file. */
  final case class Row(
      line: Int, id: String,
      kernel: Long, brdf: Long, h: Long, power: Long, contrib: Long,
      expected: Long, flags: Int,
      s: Option[Int], m: Option[Int], e: Option[Int],
      digits: Option[Seq[String]]) {
    def inputs: Seq[Long] = Seq(kernel, brdf, h, power, contrib)
  }

  /** Reads and checks a whole file; any malformed line is a [[MapmError]] naming file and line. */
  def read(path: Path, format: FloatFormat): Vector[Row] = {
    MapmError.check(Files.isRegularFile(path), s"vector file $path does not exist")
    val lines = Files.readAllLines(path).asScala.toVector
    MapmError.check(lines.nonEmpty, s"$path: empty file (expected the header ${Header.mkString(",")})")
    val head = lines.head.split(",", -1).map(_.trim).toSeq
    val withDigits = head == Header ++ DigitColumns
    MapmError.check(withDigits || head == Header || head == ResultHeader,
      s"$path:1: header '${lines.head}' is not '${(Header ++ DigitColumns).mkString(",")}' (digit columns optional; " +
        s"conventional files end at flags)")
    lines.iterator.zipWithIndex.drop(1).filter(_._1.trim.nonEmpty).map { case (text, i) =>
      parseRow(path, i + 1, text, head.length, withDigits, format)
    }.toVector
  }

  private def parseRow(path: Path, line: Int, text: String, cols: Int, withDigits: Boolean, format: FloatFormat): Row = {
    def bad(msg: String): Nothing = MapmError.fail(s"$path:$line: $msg")
    val f = text.split(",", -1).map(_.trim)
    if (f.length != cols) bad(s"${f.length} columns, expected $cols")
    val hexDigits = (format.width + 3) / 4
    def bits(c: Int): Long = {
      val s = f(c)
      if (s.length != hexDigits || !s.forall(ch => Character.digit(ch, 16) >= 0))
        bad(s"column ${(Header ++ DigitColumns)(c)} = '$s' is not $hexDigits hex digits (format $format)")
      val v = java.lang.Long.parseUnsignedLong(s, 16)
      if ((v & ~format.mask) != 0) bad(s"column ${(Header ++ DigitColumns)(c)} = '$s' has bits beyond the $format width")
      v
    }
    def optInt(c: Int): Option[Int] =
      if (c >= cols || f(c).isEmpty) None
      else Some(f(c).toIntOption.getOrElse(bad(s"column ${(Header ++ DigitColumns)(c)} = '${f(c)}' is not an integer")))
    val flags = f(7).toIntOption.filter(v => v >= 0 && v <= 7).getOrElse(bad(s"flags = '${f(7)}' is not 0..7"))
    val digits =
      if (!withDigits || f(11).isEmpty) None
      else Some((11 to 14).map { c =>
        try DigitString.parse(f(c)).toString
        catch { case e: MapmError => bad(e.getMessage) }
      })
    Row(line, f(0), bits(1), bits(2), bits(3), bits(4), bits(5), bits(6), flags, optInt(8), optInt(9), optInt(10), digits)
  }

  /** Compares the model's trace with every column of `row`; None when all agree, else a
    * one-line description of the first differing columns. */
  def mismatch(row: Row, t: ShaderChainModel.Trace, format: FloatFormat): Option[String] = {
    val diffs = Seq.newBuilder[String]
    def cmp(name: String, want: String, got: String): Unit =
      if (want != got) diffs += s"$name: expected $want, model $got"
    cmp("expected", format.hex(row.expected), format.hex(t.bits))
    cmp("flags", row.flags.toString, t.flags.toString)
    val in = t.internals
    def opt(o: Option[Any]): String = o.map(_.toString).getOrElse("")
    cmp("s", opt(row.s), opt(in.map(_.s)))
    cmp("m", opt(row.m), opt(in.map(_.m)))
    cmp("E", opt(row.e), opt(in.map(_.e)))
    row.digits.foreach { want =>
      val got = in.map(i => Seq(i.p1, i.q, i.p2, i.p3).map(_.toString)).getOrElse(Seq.fill(4)(""))
      DigitColumns.indices.foreach(k => cmp(DigitColumns(k), want(k), got(k)))
    }
    val d = diffs.result()
    if (d.isEmpty) None else Some(s"row id ${row.id} (line ${row.line}): ${d.mkString("; ")}")
  }
}
