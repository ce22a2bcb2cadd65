package mapm.model

import mapm.numerics._

import scala.collection.mutable

import mapm.MapmError

/** Photon tracing (3.1.4 step 2): the photons the photon map is built from.
  *
  * Lights are the point lights and every emissive, non-degenerate triangle (an area light of power
  * pi * area * Ke, emitting from its front side). Each photon path picks one light with probability
  * proportional to its power (the sum of its RGB channels) and starts from it:
  *  - point light: from its position, in a direction uniform over the sphere;
  *  - area light: from a point uniform over the triangle, cosine-weighted about its front normal.
  * The path carries power `P_light / p_pick`. At EVERY surface hit a [[Photon]] is stored (position,
  * the power it carries, its direction of travel, the surface normal facing it); then Russian
  * roulette lets it go on with probability `p = max(Kd)` and power scaled by `Kd / p`, in a
  * cosine-weighted direction about that normal. A path stores at most `maxBounces` photons; a photon
  * that leaves the scene is lost.
  *
  * Paths are traced until exactly `photons` photons are stored (the last path is cut off there); if
  * that took `E` paths, every photon's power is divided by `E`, so the photons together carry the
  * lights' total power once. Path k draws from its own random stream (seed, k), so the photons
  * depend only on the seed, never on the thread count. `progress` labels a progress bar over the
  * paths traced when given.
  */
object PhotonTracer {
  /** @param photons      the stored photons, in path order
    * @param emittedPaths number of photon paths traced to store them (the divisor of their power) */
  final case class Result(photons: Array[Photon], emittedPaths: Long)

  /** Traces photons into `tree`'s scene from `pointLights` and its emissive triangles. */
  def trace(tree: TriKdTree, pointLights: Seq[PointLight], photons: Int, maxBounces: Int, seed: Long,
            threads: Int = Parallel.defaultThreads, progress: Option[String] = None): Result = {
    MapmError.check(photons >= 0, s"photon count must be >= 0, got $photons")
    MapmError.check(maxBounces >= 1, s"maxBounces must be >= 1, got $maxBounces")
    if (photons == 0) return Result(Array.empty, 0)
    val paths = new Paths(tree, new Lights(tree.scene, pointLights), maxBounces, seed)
    val (stored, emitted) = collect(photons, threads, progress)(paths.photons)
    val scale = 1.0 / emitted
    Result(stored.iterator.map(p => p.copy(power = p.power * scale)).toArray, emitted)
  }

  /** The lights a path may start from: the point lights, then the scene's emitters, each picked with
    * probability proportional to its power (the sum of its RGB channels). */
  private final class Lights(scene: Scene, pointLights: Seq[PointLight]) {
    val areaPower: IndexedSeq[Vec3] = scene.emitters.map { i =>
      val t = scene.triangles(i); scene.materials(t.material).ke * (math.Pi * t.area)
    }.toIndexedSeq
    val weights: Seq[Double] = pointLights.map(l => l.power.x + l.power.y + l.power.z) ++ areaPower.map(p => p.x + p.y + p.z)
    MapmError.check(weights.sum > 0, "the scene has no light: give a point light or an emissive material (Ke)")
    val cdf: Array[Double] = Sampling.cumulative(weights)
    val nPoint: Int = pointLights.size
    def point(i: Int): PointLight = pointLights(i)
  }

  /** Photon paths through `tree`'s scene from `lights`, path k drawing from its own random stream (seed, k). */
  private final class Paths(tree: TriKdTree, lights: Lights, maxBounces: Int, seed: Long) {
    private val scene = tree.scene
    private val queries = new ThreadLocal[TriKdTree.Query] { override def initialValue() = tree.query() }

    /** The photons of path k with their un-normalised power. */
    def photons(k: Long): Array[Photon] = {
      val q = queries.get
      val rnd = Sampling.rng(seed, Sampling.PhotonStream, k)
      val li = Sampling.pick(lights.cdf, rnd)
      val prob = lights.weights(li) / lights.cdf.last
      var o: Vec3 = null
      var d: Vec3 = null
      var power: Vec3 = null
      if (li < lights.nPoint) {
        val l = lights.point(li)
        o = l.position; d = Sampling.uniformSphere(rnd); power = l.power / prob
      } else {
        val ti = scene.emitters(li - lights.nPoint)
        val n = tree.normals(ti)
        o = Sampling.pointOnTriangle(scene.triangles(ti), rnd) + n * scene.rayOffset
        d = Sampling.cosineHemisphere(n, rnd)
        power = lights.areaPower(li - lights.nPoint) / prob
      }
      val out = Array.newBuilder[Photon]
      var bounce = 0
      while (bounce < maxBounces && q.nearest(o, d)) {
        val pos = scene.clampToBounds(o + d * q.t)
        val g = tree.normals(q.triangle)
        val n = if (g.dot(d) > 0) -g else g
        out += Photon(pos, power, d, n)
        bounce += 1
        if (bounce < maxBounces) {
          val kd = scene.material(q.triangle).kd
          val survive = kd.maxComponent
          if (rnd.nextDouble() < survive) {
            power = power.mul(kd) / survive
            d = Sampling.cosineHemisphere(n, rnd)
            o = pos + n * scene.rayOffset
          } else bounce = maxBounces
        }
      }
      out.result()
    }
  }

  /** Traces paths 0, 1, ... with `path` in batches on `threads` threads until `photons` photons are
    * stored (the last path cut off there): the photons, in path order, and the paths that made them. */
  private def collect(photons: Int, threads: Int, progress: Option[String])(path: Long => Array[Photon]): (Array[Photon], Long) = {
    val stored = mutable.ArrayBuffer.empty[Photon]
    stored.sizeHint(photons)
    val maxPaths = math.max(1000000L, 100L * photons)
    var next = 0L
    var emitted = 0L
    // a bar over the paths traced; each batch adds its paths to the total
    val bar = progress.map(new Progress(_, 0L))
    try while (stored.size < photons) {
      MapmError.check(next < maxPaths,
        s"photon tracing stored only ${stored.size} of $photons photons in $next paths: the lights hardly reach the geometry")
      val perPath = if (next == 0) 1.0 else math.max(1e-4, stored.size.toDouble / next) // photons per path so far
      val batch = math.min(math.min(maxPaths - next, 1L << 20), ((photons - stored.size) / perPath * 1.05).toLong + 64).toInt
      val results = new Array[Array[Photon]](batch)
      val base = next
      bar.foreach(_.extend(batch.toLong))
      Parallel.forRange(batch, threads, progress = bar) { k => results(k) = path(base + k) }
      var k = 0
      while (k < batch && stored.size < photons) {
        val r = results(k)
        stored ++= r.iterator.take(photons - stored.size)
        if (stored.size == photons) emitted = base + k + 1
        k += 1
      }
      next += batch
    } finally bar.foreach(_.finish())
    (stored.toArray, emitted)
  }
}
