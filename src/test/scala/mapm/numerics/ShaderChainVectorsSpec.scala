package mapm.numerics

import mapm.testutil.SharedFiles
import org.scalatest.funsuite.AnyFunSuite

/** Every row of every shader-chain vector file in ../shared/vectors, every column (result,
  * flags, s, m, E and the four digit strings), reproduced by the bit-accurate model. */
class ShaderChainVectorsSpec extends AnyFunSuite with SharedFiles {
  for (v <- ShaderVectorFiles.all) {
    test(s"${v.file}: the model reproduces every row and column") {
      val rows = ShaderVectors.read(requireShared(s"vectors/${v.file}"), v.format)
      assert(rows.length == v.rows, s"${v.file}: ${rows.length} rows")
      val model = new ShaderChainModel(v.format, v.g)
      val bad = rows.flatMap(r => ShaderVectors.mismatch(r, model.trace(r.kernel, r.brdf, r.h, r.power, r.contrib), v.format))
      assert(bad.isEmpty, s"${bad.length} of ${rows.length} rows differ; first: ${bad.headOption.getOrElse("")}")
      // The files exercise every rule and every flag, so a pass covers them all.
      assert(Set(0, 1, 2, 4).subsetOf(rows.map(_.flags).toSet))
      assert(rows.count(_.digits.isDefined) > rows.length / 2)
    }
  }
}

/** The vector files of ../shared/vectors and their parameters. */
object ShaderVectorFiles {
  final case class File(file: String, format: FloatFormat, g: Int, rows: Int)
  val all: Seq[File] = Seq(
    File("fp32_g0_public.csv", FloatFormat.fp32, 0, 2000),
    File("fp32_g2_public.csv", FloatFormat.fp32, 2, 2000),
    File("fp32_g3_public.csv", FloatFormat.fp32, 3, 2000),
    File("fp16_g2_public.csv", FloatFormat.fp16, 2, 2000),
    File("fp16_g3_public.csv", FloatFormat.fp16, 3, 2000))
}
