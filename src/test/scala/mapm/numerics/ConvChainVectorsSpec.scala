package mapm.numerics

import mapm.testutil.SharedFiles
import org.scalatest.funsuite.AnyFunSuite

/** Every row of the conventional chain's vector files (../shared/vectors/conventional, made by a
  * reference written with exact rationals), reproduced by [[ConvChainModel]]; and the model
  * against the JVM's float arithmetic on random fp32 operations in the normal range. */
class ConvChainVectorsSpec extends AnyFunSuite with SharedFiles {
  for (v <- ConvVectorFiles.all) {
    test(s"conventional/${v.file}: the model reproduces every row") {
      val rows = ShaderVectors.read(requireShared(s"vectors/conventional/${v.file}"), v.format)
      assert(rows.length == v.rows, s"${v.file}: ${rows.length} rows")
      val bad = rows.flatMap(r => ShaderVectors.mismatch(r, ConvChainModel.trace(v.format, r.kernel, r.brdf, r.h, r.power, r.contrib), v.format))
      assert(bad.isEmpty, s"${bad.length} of ${rows.length} rows differ; first: ${bad.headOption.getOrElse("")}")
      assert(Set(0, 1, 2, 4).subsetOf(rows.map(_.flags).toSet))
    }
  }

  test("fp32: 200,000 random operations in the normal range equal java.lang.Float's four rounded operations") {
    val f = FloatFormat.fp32
    val rnd = new scala.util.Random(14)
    def pick(lo: Int, hi: Int): Float = java.lang.Float.intBitsToFloat(((lo + rnd.nextInt(hi - lo)) << 23) | rnd.nextInt(1 << 23))
    var checked = 0
    for (_ <- 0 until 200000) {
      val (k, b, h, p, c) = (pick(60, 190), pick(60, 190), pick(60, 190), pick(60, 190), pick(60, 190))
      val t1 = k * b; val t4 = ((t1 / h) * p) * c
      val fs = Seq(t1, t1 / h, (t1 / h) * p, t4)
      // Only where no intermediate leaves the normal range: there IEEE binary32 and the chain agree.
      if (fs.forall(x => java.lang.Math.abs(x) >= java.lang.Float.MIN_NORMAL && !x.isInfinite)) {
        val bits = Seq(k, b, h, p, c).map(x => java.lang.Float.floatToRawIntBits(x).toLong & 0xffffffffL)
        val r = ConvChainModel.colour(f, bits(0), bits(1), bits(2), bits(3), bits(4))
        assert(r.flags == 0 && r.bits == (java.lang.Float.floatToRawIntBits(t4).toLong & 0xffffffffL),
          s"${bits.map(f.hex).mkString(" ")}: model ${f.hex(r.bits)}, Float ${t4}")
        checked += 1
      }
    }
    assert(checked > 150000, s"only $checked in range")
  }
}

/** The conventional chain's vector files and their formats. */
object ConvVectorFiles {
  final case class File(file: String, format: FloatFormat, rows: Int)
  val all: Seq[File] = Seq(
    File("fp32_public.csv", FloatFormat.fp32, 2000),
    File("fp16_public.csv", FloatFormat.fp16, 2000),
    File("bf16_public.csv", FloatFormat.bf16, 2000))
}
