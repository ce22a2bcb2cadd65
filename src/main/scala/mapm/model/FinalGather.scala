package mapm.model

import mapm.numerics._

/** Final gathering (3.1.5 step 2): the query points the MAPM searches the photon map around.
  *
  * From the primary hit x of every pixel, `rays` directions are drawn cosine-weighted about the
  * normal at x that faces the camera; where such a ray hits the scene at y, y becomes a query point.
  *
  * Contribution: x and y are Lambertian (BRDF Kd/pi). With cosine-weighted directions the indirect
  * radiance leaving x towards the camera is estimated by `L(x) = (1/N) sum_i Kd(x) L(y_i)`, and the
  * photon estimate of the radiance leaving y is `L(y) = sum_photons (Kd(y)/pi) power / (pi h^2)`
  * over the photons within h of y. So each query point carries
  * `contribution_c = Kd_c(x) Kd_c(y) / N` (in [0,1]) and the photon side uses BRDF = 1/pi and
  * kernel = 1/(pi h): color = kernel * BRDF / h * power * contribution, summed into the pixel, is the
  * pixel's indirect radiance. Rays that miss, and hits whose contribution is zero in every channel
  * (a black surface), make no query point.
  *
  * Random numbers come from one stream per pixel, so the result does not depend on the thread count.
  */
object FinalGather {
  /** Query points of all pixels, in pixel order (row-major) and, within a pixel, ray order, as
    * objects (see [[gather]]). */
  def queries(tree: TriKdTree, primary: PrimaryHits, rays: Int, seed: Long,
              threads: Int = Parallel.defaultThreads): Array[QueryPoint] =
    gather(tree, primary, rays, seed, threads).toArray

  /** Values per query point while gathering: position, contribution, normal. */
  private final val Fields = 9

  /** Query points of all pixels, in pixel order (row-major) and, within a pixel, ray order, in
    * the compact [[QueryPoints]]. Each pixel's points go into one small array of doubles, then
    * into the columns; `progress` labels a progress bar over the pixels when given. */
  def gather(tree: TriKdTree, primary: PrimaryHits, rays: Int, seed: Long,
             threads: Int = Parallel.defaultThreads, progress: Option[String] = None): QueryPoints = {
    require(rays >= 1, s"final-gather rays per pixel must be >= 1, got $rays")
    val scene = tree.scene
    val perPixel = new Array[Array[Double]](primary.pixels)
    val queriesTl = new ThreadLocal[TriKdTree.Query] { override def initialValue() = tree.query() }
    val scratchTl = new ThreadLocal[Array[Double]] { override def initialValue() = new Array[Double](Fields * rays) }
    val bar = progress.map(new Progress(_, primary.pixels.toLong))
    try Parallel.forRange(primary.pixels, threads, progress = bar) { p =>
      if (primary.hit(p)) {
        val q = queriesTl.get
        val out = scratchTl.get
        val rnd = Sampling.rng(seed, Sampling.GatherStream, p)
        val n = primary.normal(p)
        val kdx = scene.material(primary.triangle(p)).kd / rays
        val origin = primary.position(p) + n * scene.rayOffset
        var m = 0
        var i = 0
        while (i < rays) {
          val d = Sampling.cosineHemisphere(n, rnd)
          if (q.nearest(origin, d)) {
            val c = kdx.mul(scene.material(q.triangle).kd)
            if (c.maxComponent > 0) {
              val g = tree.normals(q.triangle)
              val ny = if (g.dot(d) > 0) -g else g
              val y = scene.clampToBounds(origin + d * q.t)
              val o = Fields * m
              out(o) = y.x; out(o + 1) = y.y; out(o + 2) = y.z
              out(o + 3) = c.x; out(o + 4) = c.y; out(o + 5) = c.z
              out(o + 6) = ny.x; out(o + 7) = ny.y; out(o + 8) = ny.z
              m += 1
            }
          }
          i += 1
        }
        perPixel(p) = java.util.Arrays.copyOf(out, Fields * m)
      }
    } finally bar.foreach(_.finish())
    var total = 0L
    for (a <- perPixel if a != null) total += a.length / Fields
    mapm.MapmError.check(total <= Int.MaxValue - 8, s"final gather: $total query points do not fit in one array")
    val n = total.toInt
    val cols = Array.fill(Fields)(new Array[Double](n))
    val pixel = new Array[Int](n)
    var at = 0
    var p = 0
    while (p < perPixel.length) {
      val a = perPixel(p)
      if (a != null) {
        var k = 0
        while (k < a.length / Fields) {
          var f = 0
          while (f < Fields) { cols(f)(at) = a(Fields * k + f); f += 1 }
          pixel(at) = p
          at += 1; k += 1
        }
        perPixel(p) = null
      }
      p += 1
    }
    new QueryPoints(cols(0), cols(1), cols(2), pixel, cols(3), cols(4), cols(5), cols(6), cols(7), cols(8))
  }
}
