package mapm.format

import java.nio.file.Files

import mapm.MapmError
import mapm.model.FloatFormat
import org.scalatest.funsuite.AnyFunSuite

/** The expected-SO file: rows written by [[ExpectedSoFile.write]] come back from
  * [[ExpectedSoFile.read]] unchanged and sorted, at the documented offsets, and broken files are
  * one-line errors. */
class ExpectedSoFileSpec extends AnyFunSuite {
  private def rows(n: Int, seed: Int): Seq[ExpectedSoFile.Row] = {
    val rnd = new scala.util.Random(seed)
    Seq.tabulate(n)(i => ExpectedSoFile.Row(rnd.nextInt(50), i, Seq.fill(3)(rnd.nextLong() & 0xffffffffL),
      Seq.fill(3)(rnd.nextInt(8)), rnd.nextBoolean()))
  }

  test("write -> read gives the rows back, sorted by (query, photon)") {
    val file = Files.createTempFile("mapm", ".so")
    file.toFile.deleteOnExit()
    val rs = rows(500, 1)
    ExpectedSoFile.write(file, FloatFormat.fp24, 13, 7, rs)
    val back = ExpectedSoFile.read(file)
    assert(back.format == FloatFormat.fp24 && back.width == 13 && back.height == 7)
    assert(back.rows == rs.sortBy(r => (r.query, r.photon)))
    assert(Files.size(file) == 32 + 24 * rs.size)
  }

  test("bytes at the documented offsets") {
    val file = Files.createTempFile("mapm", ".so")
    file.toFile.deleteOnExit()
    ExpectedSoFile.write(file, FloatFormat.fp32, 4, 3, Seq(ExpectedSoFile.Row(7, 9, Seq(1L, 2L, 0xfedcba98L), Seq(1, 2, 5), cond = true)))
    val b = java.nio.ByteBuffer.wrap(Files.readAllBytes(file)).order(java.nio.ByteOrder.LITTLE_ENDIAN)
    assert(new String(Files.readAllBytes(file).take(8), "US-ASCII") == "MAPMSO01")
    assert(b.getInt(8) == 1 && b.get(12) == 8 && b.get(13) == 23 && b.getLong(16) == 1 && b.getInt(24) == 4 && b.getInt(28) == 3)
    assert(b.getInt(32) == 7 && b.getInt(36) == 9 && b.getInt(40) == 1 && b.getInt(44) == 2 && b.getInt(48) == 0xfedcba98)
    assert(b.getShort(52) == (1 | 2 << 3 | 5 << 6 | 1 << 9))
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
    assert(error(good.updated(8, 2.toByte)).contains("version 2"))
    assert(intercept[MapmError](ExpectedSoFile.read(file.resolveSibling("nonexistent.so"))).getMessage.contains("cannot read"))
    assert(intercept[MapmError](ExpectedSoFile.write(file, FloatFormat.fp64, 1, 1, Seq.empty)).getMessage.contains("32-bit"))
  }
}
