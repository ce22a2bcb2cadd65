package mapm.model

import mapm.numerics._

import java.util.SplittableRandom

/** Random streams and the direction/point sampling shared by photon tracing, final gather and
  * direct lighting.
  *
  * Every random decision is drawn from a stream that depends only on the scene seed, the purpose
  * (one constant per stage) and an index (a pixel or a photon path), never on the thread that runs
  * it, so results are identical for any thread count.
  */
object Sampling {
  /** Stream purposes: keep the stages' random numbers independent of each other. */
  val PhotonStream: Long = 0x50484f544f4e53L   // "PHOTONS"
  val GatherStream: Long = 0x474154484552L     // "GATHER"
  val DirectStream: Long = 0x444952454354L     // "DIRECT"

  /** SplitMix64 finaliser: a bijective 64-bit mixer. */
  def mix64(z0: Long): Long = {
    var z = z0
    z = (z ^ (z >>> 30)) * 0xbf58476d1ce4e5b9L
    z = (z ^ (z >>> 27)) * 0x94d049bb133111ebL
    z ^ (z >>> 31)
  }

  /** The random stream for item `index` of stage `stream` under scene seed `seed`. */
  def rng(seed: Long, stream: Long, index: Long): SplittableRandom =
    new SplittableRandom(mix64(mix64(seed ^ mix64(stream)) + 0x9e3779b97f4a7c15L * (index + 1)))

  /** Orthonormal tangents (t, b) with t x b = n for a unit normal n (Duff et al. 2017). */
  def tangents(n: Vec3): (Vec3, Vec3) = {
    val sign = math.copySign(1.0, n.z)
    val a = -1.0 / (sign + n.z)
    val b = n.x * n.y * a
    (Vec3(1 + sign * n.x * n.x * a, sign * b, -sign * n.x), Vec3(b, sign + n.y * n.y * a, -n.y))
  }

  /** A cosine-weighted direction about the unit normal n (density cos(theta)/pi). */
  def cosineHemisphere(n: Vec3, r: SplittableRandom): Vec3 = {
    val u1 = r.nextDouble()
    val phi = 2 * math.Pi * r.nextDouble()
    val s = math.sqrt(u1)
    val (t, b) = tangents(n)
    (t * (s * math.cos(phi)) + b * (s * math.sin(phi)) + n * math.sqrt(math.max(0.0, 1 - u1))).normalized
  }

  /** A direction uniform over the unit sphere (density 1/(4 pi)). */
  def uniformSphere(r: SplittableRandom): Vec3 = {
    val z = 1 - 2 * r.nextDouble()
    val phi = 2 * math.Pi * r.nextDouble()
    val s = math.sqrt(math.max(0.0, 1 - z * z))
    Vec3(s * math.cos(phi), s * math.sin(phi), z)
  }

  /** A point uniform over the triangle's area. */
  def pointOnTriangle(t: Triangle, r: SplittableRandom): Vec3 = {
    val su = math.sqrt(r.nextDouble())
    val b1 = 1 - su
    val b2 = su * r.nextDouble()
    t.v0 + (t.v1 - t.v0) * b1 + (t.v2 - t.v0) * b2
  }

  /** Index i with probability weights(i) / sum, from the cumulative sums `cdf` (last = sum). */
  def pick(cdf: Array[Double], r: SplittableRandom): Int = {
    val x = r.nextDouble() * cdf(cdf.length - 1)
    var lo = 0
    var hi = cdf.length - 1
    while (lo < hi) { val mid = (lo + hi) >>> 1; if (cdf(mid) > x) hi = mid else lo = mid + 1 }
    lo
  }

  /** Cumulative sums of non-negative weights. */
  def cumulative(weights: Seq[Double]): Array[Double] = weights.scanLeft(0.0)(_ + _).tail.toArray
}
