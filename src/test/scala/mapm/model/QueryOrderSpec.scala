package mapm.model

import mapm.MapmError
import mapm.numerics.{FloatFormat, Vec3}
import org.scalatest.funsuite.AnyFunSuite

/** The host's query orders: each a permutation, Morton codes against bit-by-bit interleaving, and
  * the Morton order of a grid against the Z-order curve written out by hand. */
class QueryOrderSpec extends AnyFunSuite {
  private def set(points: Seq[Vec3]): QuerySet =
    QuerySet.build(points.zipWithIndex.map { case (q, i) => QueryPoint(q, i, Vec3(0.5, 0.25, 1.0), Vec3(0, 1, 0)) }.toArray, FloatFormat.fp32)

  test("Morton codes interleave x, y, z bit by bit (x lowest), exhaustively over 3 bits per axis and at full width") {
    for (x <- 0 until 8; y <- 0 until 8; z <- 0 until 8) {
      val bits = (0 until 3).flatMap(b => Seq((x >> b) & 1, (y >> b) & 1, (z >> b) & 1))
      val want = bits.zipWithIndex.map { case (v, i) => v.toLong << i }.sum
      assert(QueryOrder.Morton.code(x, y, z) == want, (x, y, z))
    }
    val top = (1L << QueryOrder.Morton.BitsPerAxis) - 1
    assert(QueryOrder.Morton.code(top, top, top) == Long.MaxValue, "63 bits, all set")
    assert(QueryOrder.Morton.code(top, 0, 0) == (0 until 21).map(b => 1L << (3 * b)).sum)
  }

  test("a 2x2x2 grid comes out in Z order, whatever order the host gave it") {
    val cells = for (x <- 0 to 1; y <- 0 to 1; z <- 0 to 1) yield (x, y, z)
    val shuffled = new scala.util.Random(5).shuffle(cells)
    val qs = set(shuffled.map { case (x, y, z) => Vec3(10.0 + 100 * x, -3.0 + 50 * y, 7.0 + 20 * z) })
    val order = QueryOrder.Morton.of(qs)
    // Z order: x varies fastest, then y, then z.
    val zOrder = for (z <- 0 to 1; y <- 0 to 1; x <- 0 to 1) yield (x, y, z)
    assert(order.toSeq.map(shuffled) == zOrder)
  }

  test("each order is a permutation; points in one cell keep the host's order; host is the identity") {
    val rnd = new scala.util.Random(9)
    val pts = Seq.fill(500)(Vec3(rnd.nextDouble() * 500, rnd.nextDouble() * 500, rnd.nextDouble() * 500)) ++
      Seq.fill(4)(Vec3(1, 2, 3)) // four queries at one point
    val qs = set(pts)
    for (o <- QueryOrder.all) assert(o.of(qs).sorted.toSeq == (0 until qs.size), o)
    assert(QueryOrder.Host.of(qs).toSeq == (0 until qs.size))
    val m = QueryOrder.Morton.of(qs).toSeq
    assert(m.filter(_ >= 500) == Seq(500, 501, 502, 503))
    val codes = {
      val (lo, hi) = (Seq(qs.x, qs.y, qs.z).map(_.min), Seq(qs.x, qs.y, qs.z).map(_.max))
      val cells = (1L << QueryOrder.Morton.BitsPerAxis) - 1
      def q(a: Int, v: Double) = math.min(cells, ((v - lo(a)) * (cells / (hi(a) - lo(a)))).toLong)
      m.map(i => QueryOrder.Morton.code(q(0, qs.x(i)), q(1, qs.y(i)), q(2, qs.z(i))))
    }
    assert(codes == codes.sorted, "codes never decrease along the order")
    assert(QueryOrder.Morton.of(set(Seq.empty)).isEmpty && QueryOrder.Morton.of(set(Seq(Vec3(1, 1, 1)))).toSeq == Seq(0))
  }

  test("names: parsed back, an unknown one is a one-line error") {
    for (o <- QueryOrder.all) assert(QueryOrder.parse(o.name) == o)
    assert(intercept[MapmError](QueryOrder.parse("hilbert")).getMessage == "query order must be host or morton, got 'hilbert'")
  }
}
