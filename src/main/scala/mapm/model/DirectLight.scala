package mapm.model

import mapm.numerics._

/** Direct illumination at the primary hits, for the viewable image only.
  *
  * The MAPM computes indirect light (3.1); direct light is added to the picture separately and is
  * kept out of everything compared with the hardware. Per pixel, with x the primary hit, n its normal
  * facing the camera and Kd its reflectance (all surfaces Lambertian):
  *  - an emissive surface seen from its front side shows its own radiance Ke;
  *  - each point light of power P at distance r in direction l adds
  *    `Kd/pi * max(0, n.l) / r^2 * P/(4 pi)` when a shadow ray reaches it;
  *  - area lights (emissive triangles) are sampled `areaSamples` times per pixel: a triangle picked by
  *    power, a point y uniform on it, adding `Ke * Kd/pi * cos_x * cos_y / r^2 * area / p_pick`
  *    (averaged) when y's front side faces x and nothing is in between.
  * Samples come from one random stream per pixel: independent of the thread count.
  */
object DirectLight {
  /** Direct radiance per pixel (row-major), black where the primary ray misses. */
  def render(tree: TriKdTree, primary: PrimaryHits, pointLights: Seq[PointLight], areaSamples: Int, seed: Long,
             threads: Int = Parallel.defaultThreads): Array[Vec3] = {
    require(areaSamples >= 0, s"area-light samples must be >= 0, got $areaSamples")
    val scene = tree.scene
    val emitters = scene.emitters
    val emitterPower = emitters.map { i =>
      val t = scene.triangles(i); val p = scene.materials(t.material).ke * (math.Pi * t.area); p.x + p.y + p.z
    }
    val cdf = Sampling.cumulative(emitterPower)
    val totalPower = emitterPower.sum
    val out = Array.fill(primary.pixels)(Vec3.zero)
    val queries = new ThreadLocal[TriKdTree.Query] { override def initialValue() = tree.query() }
    val shortBy = 1 - 1e-7 // shadow rays stop just short of the light

    Parallel.forRange(primary.pixels, threads) { p =>
      if (primary.hit(p)) {
        val q = queries.get
        val tri = primary.triangle(p)
        val mat = scene.material(tri)
        val n = primary.normal(p)
        val brdf = mat.kd / math.Pi
        val x = primary.position(p)
        val o = x + n * scene.rayOffset
        /** Whether the segment from just off the surface to `target` is free. */
        def visible(target: Vec3): Boolean = {
          val w = target - o
          val len = w.length
          !q.occluded(o, w / len, 0, len * shortBy)
        }
        var sum = if (mat.emissive && tree.normals(tri).dot(primary.view(p)) < 0) mat.ke else Vec3.zero
        for (l <- pointLights) {
          val w = l.position - x
          val r = w.length
          val cos = n.dot(w) / r
          if (cos > 0 && visible(l.position))
            sum = sum + brdf.mul(l.power) * (cos / (r * r) / (4 * math.Pi))
        }
        if (totalPower > 0 && areaSamples > 0) {
          val rnd = Sampling.rng(seed, Sampling.DirectStream, p)
          var s = 0
          while (s < areaSamples) {
            val k = Sampling.pick(cdf, rnd)
            val t = scene.triangles(emitters(k))
            val y = Sampling.pointOnTriangle(t, rnd)
            val w = y - x
            val r = w.length
            val dir = w / r
            val cosX = n.dot(dir)
            val cosY = -tree.normals(emitters(k)).dot(dir)
            if (cosX > 0 && cosY > 0 && visible(y)) {
              val pdfArea = emitterPower(k) / totalPower / t.area
              sum = sum + scene.materials(t.material).ke.mul(brdf) * (cosX * cosY / (r * r) / pdfArea / areaSamples)
            }
            s += 1
          }
        }
        out(p) = sum
      }
    }
    out
  }
}
