package mapm.format

import java.nio.file.Files

import mapm.MapmError
import mapm.numerics.FloatFormat
import org.scalatest.funsuite.AnyFunSuite

/** The expected-SO file: rows written by [[ExpectedSoFile.write]] come back from
  * [[ExpectedSoFile.read]] unchanged and sorted, at the documented offsets, and broken files are
  * one-line errors. */
class ExpectedSoFileSpec extends AnyFunSuite {
  private def rows(n: Int, seed: Int, f: FloatFormat = FloatFormat.fp32): Seq[ExpectedSoFile.Row] = {
    val rnd = new scala.util.Random(seed)
    Seq.tabulate(n)(i => ExpectedSoFile.Row(rnd.nextInt(50), i, Seq.fill(3)(rnd.nextLong() & f.mask),
      Seq.fill(3)(rnd.nextInt(8)), rnd.nextBoolean()))
  }

  for ((f, recordBytes) <- Seq(FloatFormat.fp24 -> 24, FloatFormat.fp32 -> 24, FloatFormat(10, 40) -> 40, FloatFormat.fp64 -> 40))
    test(s"write -> read gives the rows back, sorted by (query, photon): $f, $recordBytes-byte records") {
      val file = Files.createTempFile("mapm", ".so")
      file.toFile.deleteOnExit()
      val rs = rows(500, 1, f)
      ExpectedSoFile.write(file, f, 13, 7, rs)
      val back = ExpectedSoFile.read(file)
      assert(back.format == f && back.width == 13 && back.height == 7)
      assert(back.rows == rs.sortBy(r => (r.query, r.photon)))
      assert(Files.size(file) == 32 + recordBytes * rs.size)
    }

  test("bytes at the documented offsets") {
    val file = Files.createTempFile("mapm", ".so")
    file.toFile.deleteOnExit()
    ExpectedSoFile.write(file, FloatFormat.fp32, 4, 3, Seq(ExpectedSoFile.Row(7, 9, Seq(1L, 2L, 0xfedcba98L), Seq(1, 2, 5), cond = true)))
    val b = java.nio.ByteBuffer.wrap(Files.readAllBytes(file)).order(java.nio.ByteOrder.LITTLE_ENDIAN)
    assert(new String(Files.readAllBytes(file).take(8), "US-ASCII") == "MAPMSO01")
    assert(b.getInt(8) == 2 && b.get(12) == 8 && b.get(13) == 23 && b.get(14) == 4 && b.getLong(16) == 1 && b.getInt(24) == 4 && b.getInt(28) == 3)
    assert(b.getInt(32) == 7 && b.getInt(36) == 9 && b.getInt(40) == 1 && b.getInt(44) == 2 && b.getInt(48) == 0xfedcba98)
    assert(b.getShort(52) == (1 | 2 << 3 | 5 << 6 | 1 << 9))
  }

  test("fp64 bytes at the documented offsets: 8-byte colours, the flags at 32") {
    val file = Files.createTempFile("mapm", ".so")
    file.toFile.deleteOnExit()
    val colour = Seq(java.lang.Double.doubleToLongBits(0.1), 2L, java.lang.Double.doubleToLongBits(-3.5))
    ExpectedSoFile.write(file, FloatFormat.fp64, 4, 3, Seq(ExpectedSoFile.Row(7, 9, colour, Seq(1, 2, 5), cond = true)))
    val b = java.nio.ByteBuffer.wrap(Files.readAllBytes(file)).order(java.nio.ByteOrder.LITTLE_ENDIAN)
    assert(b.capacity == 32 + 40 && b.get(12) == 11 && b.get(13) == 52 && b.get(14) == 8)
    assert(b.getInt(32) == 7 && b.getInt(36) == 9 && Seq(40, 48, 56).map(b.getLong) == colour)
    assert(b.getShort(64) == (1 | 2 << 3 | 5 << 6 | 1 << 9) && b.getShort(66) == 0 && b.getInt(68) == 0)
  }

  test("broken files are one-line errors naming the file") {
    val file = Files.createTempFile("mapm", ".so")
    file.toFile.deleteOnExit()
    ExpectedSoFile.write(file, FloatFormat.fp32, 4, 3, rows(3, 2))
    val good = Files.readAllBytes(file)
    def error(bytes: Array[Byte]): String = { Files.write(file, bytes); intercept[MapmError](ExpectedSoFile.read(file)).getMessage }
    assert(error(good.take(20)).contains("shorter than"))
    assert(error(good.take(good.length - 1)).contains("the header says 3 records"))
    assert(error(good.updated(0, 'X'.toByte)).contains("bad magic"))
    assert(error(good.updated(8, 3.toByte)).contains("version 3"))
    assert(error(good.updated(14, 8.toByte)).contains("colour fields of 8 bytes, expected 4 for fp32"))
    assert(intercept[MapmError](ExpectedSoFile.read(file.resolveSibling("nonexistent.so"))).getMessage.contains("cannot read"))
  }
}
