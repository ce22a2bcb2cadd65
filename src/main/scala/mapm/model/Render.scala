package mapm.model

import mapm.MapmError

/** Operation counts of one search-and-shade run (the quantities of Table 4.10 and a few more).
  *
  * @param queries          query points searched
  * @param treeSearchOps    tree-search operations (node visits)
  * @param shaderOps        shader operations issued by the search
  * @param shaderOpsPassing shader operations whose cond held (those that add colour)
  * @param photons          photons (= tree nodes)
  * @param treeDepth        levels of the tree (0 empty, 1 a single leaf)
  */
final case class SearchStats(queries: Long, treeSearchOps: Long, shaderOps: Long, shaderOpsPassing: Long, photons: Int, treeDepth: Int) {
  def describe: String =
    s"queries $queries, TS ops $treeSearchOps, shader ops $shaderOps (passing cond $shaderOpsPassing), photons $photons, tree depth $treeDepth"
}

/** Result of [[Render.run]]: the accumulated colour per pixel, `rgb(3*p + c)` for pixel p and
  * channel c, and the operation counts. */
final class RenderResult(val rgb: Array[Double], val stats: SearchStats) {
  def pixelCount: Int = rgb.length / 3
}

/** Every shader operation of a run in traversal order (queries in order; within a query the
  * search's issue order), for comparison with the hardware: query index, photon node index, the
  * three colour channels as format bit patterns, and cond. Colour is computed whether or not cond
  * holds, as the SOA does. */
final class ShaderOpList(
    val query: Array[Int],
    val node: Array[Int],
    val color: Array[Array[Long]],
    val cond: Array[Boolean],
    val stats: SearchStats
) {
  def size: Int = query.length
}

/** The search-and-shade engine: tree search ([[TreeSearcher]]) and shading ([[ShadeArith]]) of
  * every query against a [[PhotonMap]].
  *
  * Accumulation: the colours of a query's passing shader operations are summed in binary64 in
  * issue order, then the per-query sums are added to their pixels in query order, so the image is
  * the same for any number of threads.
  */
object Render {
  private def check(map: PhotonMap, queries: QuerySet, arith: ShadeArith): Unit =
    MapmError.check(map.format == queries.format && map.format == arith.format,
      s"render: photon map (${map.format}), queries (${queries.format}) and shading arithmetic (${arith.format}) must use one format")

  /** Searches and shades every query; `pixelCount` pixels (every query's pixel must be below it).
    * Runs on `threads` threads; `progress` labels a progress bar when given. */
  def run(map: PhotonMap, queries: QuerySet, pixelCount: Int, arith: ShadeArith, threads: Int = 2,
          progress: Option[String] = None): RenderResult = {
    check(map, queries, arith)
    MapmError.check(threads >= 1, s"render: thread count must be at least 1, got $threads")
    val nq = queries.size
    var i = 0
    while (i < nq) {
      MapmError.check(queries.pixel(i) < pixelCount, s"query $i: pixel ${queries.pixel(i)} outside an image of $pixelCount pixels")
      i += 1
    }
    val sums = new Array[Double](3 * nq)
    val next = new java.util.concurrent.atomic.AtomicInteger(0)
    val chunk = 256
    val bar = progress.map(new Progress(_, nq.toLong))
    val workers = Array.fill(threads)(new Worker(map, queries, arith, sums))
    val ts = workers.map { w =>
      new Thread(() => {
        var start = next.getAndAdd(chunk)
        while (start < nq) {
          val end = math.min(nq, start + chunk)
          w.runRange(start, end)
          bar.foreach(_.advance((end - start).toLong))
          start = next.getAndAdd(chunk)
        }
      })
    }
    val failure = new java.util.concurrent.atomic.AtomicReference[Throwable](null)
    ts.foreach(_.setUncaughtExceptionHandler((_, e) => failure.compareAndSet(null, e)))
    ts.foreach(_.start())
    ts.foreach(_.join())
    bar.foreach(_.finish())
    if (failure.get != null) throw failure.get
    val rgb = new Array[Double](3 * pixelCount)
    i = 0
    while (i < nq) {
      val p = 3 * queries.pixel(i)
      rgb(p) += sums(3 * i); rgb(p + 1) += sums(3 * i + 1); rgb(p + 2) += sums(3 * i + 2)
      i += 1
    }
    new RenderResult(rgb, SearchStats(nq.toLong, workers.map(_.tsOps).sum, workers.map(_.soOps).sum,
      workers.map(_.passing).sum, map.size, map.tree.levels))
  }

  /** One thread's searcher, counters and shading loop; writes the per-query sums. */
  private final class Worker(map: PhotonMap, queries: QuerySet, arith: ShadeArith, sums: Array[Double]) {
    private val searcher = new TreeSearcher(map.search)
    private val toDouble: Long => Double = arith match {
      case r: RoundedShadeArith => r.toDouble
      case _                    => map.format.decode
    }
    var tsOps = 0L
    var soOps = 0L
    var passing = 0L

    def runRange(from: Int, until: Int): Unit = {
      val h = map.h; val hv = map.hValue
      val px = map.px; val py = map.py; val pz = map.pz
      val pr = map.power(0); val pg = map.power(1); val pb = map.power(2)
      val kernel = map.kernel; val brdf = map.brdf
      val so = searcher.so
      var q = from
      while (q < until) {
        searcher.search(queries.x(q), queries.y(q), queries.z(q), hv)
        val qx = queries.qx(q); val qy = queries.qy(q); val qz = queries.qz(q)
        val cr = queries.contribution(0)(q); val cg = queries.contribution(1)(q); val cb = queries.contribution(2)(q)
        var r = 0.0; var g = 0.0; var b = 0.0
        var k = 0
        val n = searcher.soCount
        while (k < n) {
          val i = so(k)
          if (arith.cond(qx, qy, qz, px(i), py(i), pz(i), h)) {
            r += toDouble(arith.color(kernel(i), brdf(i), h, pr(i), cr))
            g += toDouble(arith.color(kernel(i), brdf(i), h, pg(i), cg))
            b += toDouble(arith.color(kernel(i), brdf(i), h, pb(i), cb))
            passing += 1
          }
          k += 1
        }
        sums(3 * q) = r; sums(3 * q + 1) = g; sums(3 * q + 2) = b
        tsOps += searcher.tsCount
        soOps += n
        q += 1
      }
    }
  }

  /** Every shader operation of every query, in traversal order (one thread; meant for small scenes
    * and golden comparisons with the hardware). */
  def shaderOps(map: PhotonMap, queries: QuerySet, arith: ShadeArith): ShaderOpList = {
    check(map, queries, arith)
    val searcher = new TreeSearcher(map.search)
    val qi = Array.newBuilder[Int]; val ni = Array.newBuilder[Int]
    val col = Array.fill(3)(Array.newBuilder[Long]); val cd = Array.newBuilder[Boolean]
    var ts = 0L; var passing = 0L
    for (q <- 0 until queries.size) {
      searcher.search(queries.x(q), queries.y(q), queries.z(q), map.hValue)
      ts += searcher.tsCount
      for (k <- 0 until searcher.soCount) {
        val i = searcher.so(k)
        qi += q; ni += i
        for (c <- 0 until 3)
          col(c) += arith.color(map.kernel(i), map.brdf(i), map.h, map.power(c)(i), queries.contribution(c)(q))
        val ok = arith.cond(queries.qx(q), queries.qy(q), queries.qz(q), map.px(i), map.py(i), map.pz(i), map.h)
        cd += ok
        if (ok) passing += 1
      }
    }
    val query = qi.result()
    new ShaderOpList(query, ni.result(), col.map(_.result()), cd.result(),
      SearchStats(queries.size.toLong, ts, query.length.toLong, passing, map.size, map.tree.levels))
  }
}
