package mapm.model

import mapm.numerics._

import org.scalatest.funsuite.AnyFunSuite

class SamplingSpec extends AnyFunSuite {
  test("cosine-weighted directions: unit, in the hemisphere, E[cos] = 2/3 and P(cos > c) = 1 - c^2") {
    val rnd = Sampling.rng(1, 2, 3)
    for (n <- Seq(Vec3(0, 0, 1), Vec3(0, 0, -1), Vec3(1, 2, -3).normalized, Vec3(-1, 0, 0))) {
      val m = 200000
      val cos = Array.fill(m) {
        val d = Sampling.cosineHemisphere(n, rnd)
        assert(math.abs(d.length - 1) < 1e-12)
        d.dot(n)
      }
      assert(cos.forall(_ >= 0))
      assert(math.abs(cos.sum / m - 2.0 / 3) < 0.005)
      for (c <- Seq(0.25, 0.5, 0.9)) assert(math.abs(cos.count(_ > c).toDouble / m - (1 - c * c)) < 0.005)
    }
  }

  test("uniform sphere directions: unit, E[z] = 0, P(z > c) = (1 - c) / 2") {
    val rnd = Sampling.rng(4, 5, 6)
    val m = 200000
    val d = Array.fill(m)(Sampling.uniformSphere(rnd))
    assert(d.forall(v => math.abs(v.length - 1) < 1e-12))
    for (c <- Seq(-0.5, 0.0, 0.7)) assert(math.abs(d.count(_.z > c).toDouble / m - (1 - c) / 2) < 0.005)
    assert(math.abs(d.map(_.x).sum / m) < 0.01)
  }

  test("points on a triangle: inside, uniform (each of the 4 midpoint sub-triangles gets 1/4)") {
    val t = Triangle(Vec3(0, 0, 0), Vec3(4, 0, 0), Vec3(0, 2, 0), 0)
    val rnd = Sampling.rng(7, 8, 9)
    val m = 100000
    val counts = new Array[Int](4)
    for (_ <- 0 until m) {
      val p = Sampling.pointOnTriangle(t, rnd)
      // barycentrics from the legs: u along x (0..4), v along y (0..2)
      val u = p.x / 4; val v = p.y / 2
      assert(u >= 0 && v >= 0 && u + v <= 1 + 1e-12 && p.z == 0)
      counts(if (u > 0.5) 1 else if (v > 0.5) 2 else if (u + v < 0.5) 0 else 3) += 1
    }
    for (c <- counts) assert(math.abs(c.toDouble / m - 0.25) < 0.01)
  }

  test("streams differ by seed, purpose and index, and repeat for the same ones") {
    def first(s: Long, p: Long, i: Long) = Sampling.rng(s, p, i).nextLong()
    assert(first(1, 2, 3) == first(1, 2, 3))
    assert(Set(first(1, 2, 3), first(2, 2, 3), first(1, 3, 3), first(1, 2, 4)).size == 4)
  }

  test("pick follows the weights") {
    val cdf = Sampling.cumulative(Seq(1.0, 0.0, 3.0))
    val rnd = Sampling.rng(1, 1, 1)
    val counts = new Array[Int](3)
    for (_ <- 0 until 100000) counts(Sampling.pick(cdf, rnd)) += 1
    assert(counts(1) == 0 && math.abs(counts(0) / 100000.0 - 0.25) < 0.01)
  }

  test("Parallel.forRange visits every index once for any thread count and passes exceptions on") {
    for (threads <- Seq(1, 2, 5); n <- Seq(0, 1, 63, 64, 1000)) {
      val seen = new java.util.concurrent.atomic.AtomicIntegerArray(n)
      Parallel.forRange(n, threads, chunk = 7)(i => seen.incrementAndGet(i))
      assert((0 until n).forall(seen.get(_) == 1))
    }
    val e = intercept[IllegalStateException](Parallel.forRange(100, 2, 3)(i => if (i == 50) throw new IllegalStateException("x")))
    assert(e.getMessage == "x")
  }
}
