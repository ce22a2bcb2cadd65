package mapm.model

/** The order in which the host streams a frame's queries to the MAPM. The hardware takes any
  * order, and neither the frame nor the multiset of (query, photon) results depends on it (the
  * harness accumulates the colours exactly). What it changes is locality: the queries that the
  * TSMs search at once, and so the shader operations that meet in each SOM's SOP L1, touch the
  * same photons when they lie close together (treelet and ray sorting in ray tracers: Aila and
  * Karras, HPG 2010). */
sealed abstract class QueryOrder(name: String) extends mapm.Choice(name) {
  /** The stream order of `queries`: a permutation of their indices. */
  def of(queries: QuerySet): Array[Int]
}

object QueryOrder extends mapm.Choices[QueryOrder] {
  /** The queries' own order, as the renderer makes them: pixel by pixel in scan order, each
    * pixel's final-gather rays in turn (the dissertation's host). */
  case object Host extends QueryOrder("host") {
    def of(queries: QuerySet): Array[Int] = Array.tabulate(queries.size)(identity)
  }

  /** Along a Morton (Z-order) curve through the query points' bounding box, [[Morton.BitsPerAxis]]
    * bits per axis; points in the same cell keep their host order. */
  case object Morton extends QueryOrder("morton") {
    def of(queries: QuerySet): Array[Int] = {
      val axes = Seq(queries.x, queries.y, queries.z)
      val cells = (1L << Morton.BitsPerAxis) - 1
      val quantized = axes.map { v =>
        val (lo, hi) = if (v.isEmpty) (0.0, 0.0) else (v.min, v.max)
        val scale = if (hi > lo) cells / (hi - lo) else 0.0
        v.map(c => math.min(cells, math.max(0L, ((c - lo) * scale).toLong)))
      }
      val code = Array.tabulate(queries.size)(i => Morton.code(quantized(0)(i), quantized(1)(i), quantized(2)(i)))
      Array.tabulate(queries.size)(identity).sortBy(i => (code(i), i))
    }

    /** Bits of each axis in the code: 3 x 21 = 63 bits. */
    val BitsPerAxis = 21

    /** The Morton code of cell (x, y, z): bit b of x at bit 3b, of y at 3b + 1, of z at 3b + 2. */
    def code(x: Long, y: Long, z: Long): Long = {
      var c = 0L
      for (b <- 0 until BitsPerAxis)
        c |= ((x >> b) & 1) << (3 * b) | ((y >> b) & 1) << (3 * b + 1) | ((z >> b) & 1) << (3 * b + 2)
      c
    }
  }

  val all: Seq[QueryOrder] = Seq(Host, Morton)

  protected def unknown(s: String): String = s"query order must be ${all.mkString(" or ")}, got '$s'"
}
