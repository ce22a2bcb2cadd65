package mapm.model

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
  /** Query points of all pixels, in pixel order (row-major) and, within a pixel, ray order. */
  def queries(tree: TriKdTree, primary: PrimaryHits, rays: Int, seed: Long,
              threads: Int = Parallel.defaultThreads): Array[QueryPoint] = {
    require(rays >= 1, s"final-gather rays per pixel must be >= 1, got $rays")
    val scene = tree.scene
    val perPixel = new Array[Array[QueryPoint]](primary.pixels)
    val queriesTl = new ThreadLocal[TriKdTree.Query] { override def initialValue() = tree.query() }
    Parallel.forRange(primary.pixels, threads) { p =>
      if (primary.hit(p)) {
        val q = queriesTl.get
        val rnd = Sampling.rng(seed, Sampling.GatherStream, p)
        val n = primary.normal(p)
        val kdx = scene.material(primary.triangle(p)).kd / rays
        val origin = primary.position(p) + n * scene.rayOffset
        val out = Array.newBuilder[QueryPoint]
        var i = 0
        while (i < rays) {
          val d = Sampling.cosineHemisphere(n, rnd)
          if (q.nearest(origin, d)) {
            val c = kdx.mul(scene.material(q.triangle).kd)
            if (c.maxComponent > 0) {
              val g = tree.normals(q.triangle)
              val ny = if (g.dot(d) > 0) -g else g
              out += QueryPoint(scene.clampToBounds(origin + d * q.t), p, c, ny)
            }
          }
          i += 1
        }
        perPixel(p) = out.result()
      }
    }
    perPixel.iterator.filter(_ != null).flatten.toArray
  }
}
