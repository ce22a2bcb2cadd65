package mapm.model

import mapm.numerics._

/** The operations a frame gives its arithmetic units, in search order, as bit patterns of the
  * frame's format: the inputs of every shader operation (for the SOA and the cond check) and of
  * every tree-search operation (for the TSA). The cost flow simulates the synthesized units on
  * them, so that their switching activity is the activity of a real frame.
  */
object FrameOps {
  /** One shader operation's inputs, in the order of the SOA's data ports: kernel, BRDF, h, power
    * r/g/b, contribution r/g/b, query x/y/z, photon x/y/z. */
  final case class So(inputs: Array[Long]) {
    def kernel: Long = inputs(0); def brdf: Long = inputs(1); def h: Long = inputs(2)
    def power(c: Int): Long = inputs(3 + c); def contrib(c: Int): Long = inputs(6 + c)
    def q(axis: Int): Long = inputs(9 + axis); def p(axis: Int): Long = inputs(12 + axis)
  }

  /** One tree-search operation: query coordinate p on the node's axis, radius h, split s. */
  final case class Ts(p: Long, h: Long, s: Long)

  /** Searches the queries in order and lets `take` add each search's operations to the list,
    * until it holds `limit`. */
  private def collect[T](map: PhotonMap, queries: QuerySet, limit: Int)(
      take: (TreeSearcher, Int, scala.collection.mutable.ArrayBuffer[T]) => Unit): IndexedSeq[T] = {
    val out = scala.collection.mutable.ArrayBuffer.empty[T]
    val searcher = new TreeSearcher(map.search)
    var q = 0
    while (q < queries.size && out.length < limit) {
      searcher.search(queries.x(q), queries.y(q), queries.z(q), map.hValue)
      take(searcher, q, out)
      q += 1
    }
    out.take(limit).toIndexedSeq
  }

  /** The first `limit` shader operations of the frame's queries, in search order. */
  def shaderOps(map: PhotonMap, queries: QuerySet, limit: Int): IndexedSeq[So] =
    collect[So](map, queries, limit) { (searcher, q, out) =>
      for (k <- 0 until searcher.soCount) {
        val i = searcher.so(k)
        out += So(Array(map.kernel(i), map.brdf(i), map.h, map.power(0)(i), map.power(1)(i), map.power(2)(i),
          queries.contribution(0)(q), queries.contribution(1)(q), queries.contribution(2)(q),
          queries.qx(q), queries.qy(q), queries.qz(q), map.px(i), map.py(i), map.pz(i)))
      }
    }

  /** The first `limit` tree-search operations of the frame's queries, in search order. */
  def treeSearchOps(map: PhotonMap, queries: QuerySet, limit: Int): IndexedSeq[Ts] =
    collect[Ts](map, queries, limit) { (searcher, q, out) =>
      val coord = Array(queries.qx(q), queries.qy(q), queries.qz(q))
      for (k <- 0 until searcher.tsCount) {
        val i = searcher.visited(k)
        out += Ts(coord(NodeWord.axis(map.search.word(i))), map.h, map.split(i))
      }
    }
}
