package mapm.numerics

/** The cond reference of a tiny format as operation tables: every rounded operation the cond
  * sequence uses (sub, add, mul, lt) on every pair of bit patterns, each entry computed by
  * [[ExactFloat]] (exact rationals, correctly rounded), with a second table per operation that
  * says whether the exact result was a rounding tie. A whole cond case is then ten table
  * lookups, so that all 2^(7·width) cases of a 4-bit format stay fast. */
final class CondTables(val f: FloatFormat) {
  require(f.width <= 6, s"operation tables are for tiny formats, not $f")
  val size: Int = 1 << f.width

  private def table(op: (ExactFloat.Value, ExactFloat.Value) => ExactFloat.Value): (Array[Int], Array[Boolean]) = {
    val r = new Array[Int](size * size); val t = new Array[Boolean](size * size)
    for (a <- 0 until size; b <- 0 until size) {
      val v = op(ExactFloat.decode(f, a.toLong), ExactFloat.decode(f, b.toLong))
      r(a * size + b) = ExactFloat.encode(f, v).toInt
      t(a * size + b) = ExactFloat.isTie(f, v)
    }
    (r, t)
  }
  /** a − b, a + b, a · b: result pattern and tie flag at index a·size + b. */
  val (sub, subTie) = table((a, b) => ExactFloat.sum(a, ExactFloat.negate(b)))
  val (add, addTie) = table(ExactFloat.sum)
  val (mul, mulTie) = table(ExactFloat.product)
  /** a < b at index a·size + b (false with a NaN). */
  val lt: Array[Boolean] = Array.tabulate(size * size)(i => ExactFloat.lt(f, (i / size).toLong, (i % size).toLong))
  /** a and b are equal numbers (neither a NaN, neither less than the other). */
  val eq: Array[Boolean] = Array.tabulate(size * size) { i =>
    val (a, b) = ((i / size).toLong, (i % size).toLong)
    !f.isNaN(a) && !f.isNaN(b) && !lt(i) && !ExactFloat.lt(f, b, a)
  }
}

object CondTables {
  /** Case k of the exhaustive enumeration of format `f`: operand j (qx, qy, qz, px, py, pz, h
    * for j = 0 … 6) is bits w·j … w·j + w − 1 of k, w = f.width. */
  def operand(f: FloatFormat, k: Long, j: Int): Int = ((k >>> (f.width * j)) & f.mask).toInt
}
