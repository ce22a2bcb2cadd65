package mapm.model

import mapm.numerics._

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
  * three colour channels as format bit patterns, their SOA flags (OVF 1, UNF 2, INV 4; present
  * when the arithmetic models them, [[ShadeArith.hasFlags]]) and cond. Colour is computed whether
  * or not cond holds, as the SOA does. */
final class ShaderOpList(
    val query: Array[Int],
    val node: Array[Int],
    val color: Array[Array[Long]],
    val flags: Option[Array[Array[Byte]]],
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
    val order = spatialOrder(queries, map.tree.box)
    val photons = new Photons(map)
    val workers = Progress.maybe(progress, nq.toLong) { bar =>
      Parallel.forChunks(nq, threads, chunk = 256, bar)(new Worker(map, photons, queries, arith, sums, new TreeSearcher(map.search))) {
        (w, from, until) => w.runRange(order, from, until)
      }
    }
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

  /** Query indices sorted along a Morton (Z-order) curve over `box`, so that consecutive queries
    * are near each other and reuse the tree nodes and photons already in the cache. Only the
    * processing order changes: each query's sum is computed alone and the image is reduced in
    * query order. */
  private def spatialOrder(queries: QuerySet, box: Box): Array[Int] = {
    val ext = box.extent
    def cell(v: Double, lo: Double, e: Double): Long =
      if (e <= 0) 0L else math.max(0L, math.min(1023L, ((v - lo) / e * 1024).toLong))
    def spread(v: Long): Long = { // bits 0..9 to 0, 3, 6, ..., 27
      var r = 0L; var b = 0
      while (b < 10) { r |= ((v >>> b) & 1L) << (3 * b); b += 1 }
      r
    }
    val keys = Array.tabulate(queries.size) { q =>
      val m = spread(cell(queries.x(q), box.lo.x, ext.x)) | (spread(cell(queries.y(q), box.lo.y, ext.y)) << 1) |
        (spread(cell(queries.z(q), box.lo.z, ext.z)) << 2)
      (m << 32) | q.toLong
    }
    java.util.Arrays.sort(keys)
    keys.map(k => (k & 0xffffffffL).toInt)
  }

  /** Photon fields side by side per node, so that a shader operation touches one place in memory:
    * positions x, y, z as bits and as exact doubles (read by every shader operation), and power
    * r, g, b, kernel, BRDF (read when cond holds). */
  private final class Photons(map: PhotonMap) {
    val n: Int = map.size
    val bits: Array[Long] = new Array[Long](3 * n)
    val value: Array[Double] = new Array[Double](3 * n)
    val shade: Array[Long] = new Array[Long](5 * n)
    for (i <- 0 until n) {
      bits(3 * i) = map.px(i); bits(3 * i + 1) = map.py(i); bits(3 * i + 2) = map.pz(i)
      for (k <- 0 until 3) value(3 * i + k) = map.format.decode(bits(3 * i + k))
      val o = 5 * i
      shade(o) = map.power(0)(i); shade(o + 1) = map.power(1)(i); shade(o + 2) = map.power(2)(i)
      shade(o + 3) = map.kernel(i); shade(o + 4) = map.brdf(i)
    }
  }

  /** cond of one shader operation. With (lo, hi) from [[ShadeArith.condClearBounds]], one whose
    * squared distance `e2`, computed in plain doubles from the exact values, is clearly below lo
    * passes and one clearly above hi fails; only the others call [[ShadeArith.cond]] on the
    * query's (q) and photon's (p) coordinates as format bits. The double value is within a
    * relative 1e-15 (plus underflow, below 1e-300) of the exact one, far inside the 1e-12 margin.
    */
  private def cond(arith: ShadeArith, e2: Double, lo: Double, hi: Double, qx: Long, qy: Long, qz: Long,
                   px: Long, py: Long, pz: Long, h: Long): Boolean = {
    val clearIn = e2 * (1 + 1e-12) + 1e-300 < lo
    // `|`, not `||`: whether the SO passes must not steer a branch (it would mispredict)
    if (clearIn | e2 * (1 - 1e-12) > hi) clearIn else arith.cond(qx, qy, qz, px, py, pz, h)
  }

  /** One thread's searcher, counters and shading loop; writes the per-query sums. */
  private final class Worker(map: PhotonMap, photons: Photons, queries: QuerySet, arith: ShadeArith,
                             sums: Array[Double], searcher: TreeSearcher) {
    var tsOps = 0L
    var soOps = 0L
    var passing = 0L
    // per-query scratch: passing photons and their gathered shading fields (grown on demand)
    private var passed = new Array[Int](1024)
    private var fields = new Array[Long](5 * 1024)

    /** Runs queries order(from until until). */
    def runRange(order: Array[Int], from: Int, until: Int): Unit = {
      val searcher = this.searcher; val arith = this.arith
      var passed = this.passed; var fields = this.fields
      val pos = photons.value; val posBits = photons.bits; val rec = photons.shade
      val out = new Array[Long](3)
      val vals = new Array[Double](3)
      var ts = 0L; var sos = 0L; var pass = 0L
      val h = map.h; val hv = map.hValue
      val (lo, hi) = arith.condClearBounds(h)
      val so = searcher.so
      val qxs = queries.qx; val qys = queries.qy; val qzs = queries.qz
      val xs = queries.x; val ys = queries.y; val zs = queries.z
      val crs = queries.contribution(0); val cgs = queries.contribution(1); val cbs = queries.contribution(2)
      var t = from
      while (t < until) {
        val q = order(t)
        val x = xs(q); val y = ys(q); val z = zs(q)
        searcher.search(x, y, z, hv)
        val n = searcher.soCount
        if (n > passed.length) {
          passed = new Array[Int](n); fields = new Array[Long](5 * n)
          this.passed = passed; this.fields = fields
        }
        // 1. cond for every SO; the passing ones, in order, into `passed` (no data-dependent
        //    branch on the common path, so the position loads of many SOs overlap)
        var m = 0
        var k = 0
        while (k < n) {
          val i = so(k)
          val o = 3 * i
          val ex = x - pos(o); val ey = y - pos(o + 1); val ez = z - pos(o + 2)
          val ok = cond(arith, ex * ex + ey * ey + ez * ez, lo, hi, qxs(q), qys(q), qzs(q), posBits(o), posBits(o + 1), posBits(o + 2), h)
          passed(m) = i
          m += (if (ok) 1 else 0)
          k += 1
        }
        // 2. gather the shading fields of the passing photons (independent loads again)
        var j = 0
        while (j < m) {
          val s = 5 * passed(j)
          val d = 5 * j
          fields(d) = rec(s); fields(d + 1) = rec(s + 1); fields(d + 2) = rec(s + 2); fields(d + 3) = rec(s + 3); fields(d + 4) = rec(s + 4)
          j += 1
        }
        // 3. shade and accumulate in issue order
        val cr = crs(q); val cg = cgs(q); val cb = cbs(q)
        var r = 0.0; var g = 0.0; var b = 0.0
        j = 0
        while (j < m) {
          val d = 5 * j
          arith.shadeValues(fields(d + 3), fields(d + 4), h, fields(d), fields(d + 1), fields(d + 2), cr, cg, cb, out, vals)
          r += vals(0); g += vals(1); b += vals(2)
          j += 1
        }
        pass += m
        sums(3 * q) = r; sums(3 * q + 1) = g; sums(3 * q + 2) = b
        ts += searcher.tsCount
        sos += n
        t += 1
      }
      tsOps += ts; soOps += sos; passing += pass
    }
  }

  /** Every shader operation of every query, in traversal order, on `threads` threads (each takes
    * blocks of consecutive queries; the blocks are joined in query order, so the list is the same
    * for any thread count). Meant for golden comparisons with the hardware: every SO is shaded,
    * with flags when `arith` has them. */
  def shaderOps(map: PhotonMap, queries: QuerySet, arith: ShadeArith, threads: Int = 1): ShaderOpList = {
    check(map, queries, arith)
    MapmError.check(threads >= 1, s"shader ops: thread count must be at least 1, got $threads")
    val nq = queries.size
    val block = 64
    val parts = new Array[OpBlock]((nq + block - 1) / block)
    Parallel.forChunks(parts.length, threads, chunk = 1)((new TreeSearcher(map.search), new FormatBits(map.format))) {
      case ((searcher, codec), b, _) => parts(b) = new OpBlock(map, queries, arith, searcher, codec, b * block, math.min(nq, (b + 1) * block))
    }
    val total = parts.map(_.size.toLong).sum
    MapmError.check(total <= Int.MaxValue, s"shader ops: $total operations do not fit in one list")
    val n = total.toInt
    val query = new Array[Int](n); val node = new Array[Int](n); val cond = new Array[Boolean](n)
    val color = Array.fill(3)(new Array[Long](n))
    val flags = if (arith.hasFlags) Some(Array.fill(3)(new Array[Byte](n))) else None
    var at = 0
    var tsOps = 0L
    for (b <- parts.indices) {
      val p = parts(b)
      tsOps += p.tsOps
      System.arraycopy(p.query, 0, query, at, p.size); System.arraycopy(p.node, 0, node, at, p.size)
      System.arraycopy(p.cond, 0, cond, at, p.size)
      for (c <- 0 until 3) {
        System.arraycopy(p.color(c), 0, color(c), at, p.size)
        flags.foreach(f => System.arraycopy(p.flags(c), 0, f(c), at, p.size))
      }
      at += p.size
      parts(b) = null
    }
    new ShaderOpList(query, node, color, flags, cond,
      SearchStats(nq.toLong, tsOps, n.toLong, cond.count(identity).toLong, map.size, map.tree.levels))
  }

  /** The shader operations of queries from until until, in traversal order; cond as [[cond]]
    * decides it. */
  private final class OpBlock(map: PhotonMap, queries: QuerySet, arith: ShadeArith, searcher: TreeSearcher,
                              codec: FormatBits, from: Int, until: Int) {
    var size = 0
    var tsOps = 0L
    var query = new Array[Int](256)
    var node = new Array[Int](256)
    var cond = new Array[Boolean](256)
    var color: Array[Array[Long]] = Array.fill(3)(new Array[Long](256))
    var flags: Array[Array[Byte]] = Array.fill(3)(new Array[Byte](256))

    private def grow(need: Int): Unit = if (need > query.length) {
      val cap = math.max(need, 2 * query.length)
      query = java.util.Arrays.copyOf(query, cap); node = java.util.Arrays.copyOf(node, cap)
      cond = java.util.Arrays.copyOf(cond, cap)
      color = color.map(java.util.Arrays.copyOf(_, cap)); flags = flags.map(java.util.Arrays.copyOf(_, cap))
    }

    {
      val out = new Array[Long](3)
      val vals = new Array[Double](3)
      val fl = new Array[Int](3)
      val withFlags = arith.hasFlags
      val h = map.h
      val (lo, hi) = arith.condClearBounds(h)
      for (q <- from until until) {
        val x = queries.x(q); val y = queries.y(q); val z = queries.z(q)
        searcher.search(x, y, z, map.hValue)
        tsOps += searcher.tsCount
        val n = searcher.soCount
        grow(size + n)
        val cr = queries.contribution(0)(q); val cg = queries.contribution(1)(q); val cb = queries.contribution(2)(q)
        for (k <- 0 until n) {
          val i = searcher.so(k)
          query(size) = q; node(size) = i
          if (withFlags) arith.shadeFlags(map.kernel(i), map.brdf(i), h, map.power(0)(i), map.power(1)(i), map.power(2)(i), cr, cg, cb, out, fl)
          else arith.shade(map.kernel(i), map.brdf(i), h, map.power(0)(i), map.power(1)(i), map.power(2)(i), cr, cg, cb, out)
          for (c <- 0 until 3) { color(c)(size) = out(c); flags(c)(size) = fl(c).toByte }
          val ex = x - codec.toDouble(map.px(i)); val ey = y - codec.toDouble(map.py(i)); val ez = z - codec.toDouble(map.pz(i))
          cond(size) = Render.cond(arith, ex * ex + ey * ey + ez * ez, lo, hi, queries.qx(q), queries.qy(q), queries.qz(q),
            map.px(i), map.py(i), map.pz(i), h)
          size += 1
        }
      }
    }
  }
}
