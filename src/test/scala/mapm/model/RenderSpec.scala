package mapm.model

import mapm.numerics._

import mapm.MapmError
import org.scalatest.funsuite.AnyFunSuite

class RenderSpec extends AnyFunSuite {
  private def photon(p: Vec3, power: Vec3) = Photon(p, power, Vec3(0, -1, 0), Vec3(0, 1, 0))

  test("shader-op list on the Table 3.1 tree: the example searches' SOs, with colour and cond") {
    val f = FloatFormat.fp32
    val powers = Table31.photons.indices.map(i => Vec3(0.1 * (i + 1), 0.2, 0.05 * (7 - i)))
    val map = PhotonMap.build(Table31.photons.zip(powers).map { case (p, w) => photon(p, w) }, Table31.box, f, 100.0)
    val qs = Seq(Vec3(0, 358.739, 280.736), Vec3(0, 473.547, 255.165), Vec3(213.296, 0, 26.6906))
    val queries = QuerySet.build(qs.zipWithIndex.map { case (q, i) => QueryPoint(q, i, Vec3(0.5, 0.25, 1.0), Vec3(0, 1, 0)) }.toArray, f)
    val arith = ShadeArith.rounded(f)
    val list = Render.shaderOps(map, queries, arith)
    assert(list.query.toSeq == Seq(0, 0, 0, 1, 1, 1, 1, 1, 2, 2, 2))
    assert(list.node.toSeq == Seq(5, 6, 4, 0, 2, 5, 6, 4, 2, 3, 1))
    assert(list.stats == SearchStats(3, 7, 11, list.cond.count(identity).toLong, 7, 3))
    // cond against the exact distance of the Table 3.1 photons (none is near the boundary)
    for (k <- 0 until list.size) {
      val d = qs(list.query(k)) - map.tree.position(list.node(k))
      assert(list.cond(k) == (d.length < 100), s"op $k")
      val ph = map.tree.photon(list.node(k))
      for (c <- 0 until 3) {
        val want = powers(ph)(c) * Seq(0.5, 0.25, 1.0)(c) / (math.Pi * math.Pi * 100 * 100)
        assert(math.abs(f.decode(list.color(c)(k)) / want - 1) < 1e-6)
      }
    }
    assert(list.cond.count(identity) == 1 && list.cond(3)) // only node 0 lies within 100 (of query 1)
  }

  private def randomScene(seed: Int, nPhotons: Int, nQueries: Int, pixels: Int, f: FloatFormat, h: Double) = {
    val rnd = new scala.util.Random(seed)
    val box = Box(Vec3(0, 0, 0), Vec3(100, 80, 120))
    def pt() = Vec3(rnd.nextDouble() * 100, rnd.nextDouble() * 80, rnd.nextDouble() * 120)
    val photons = Array.fill(nPhotons)(photon(pt(), Vec3(rnd.nextDouble(), rnd.nextDouble(), rnd.nextDouble())))
    val queries = Array.fill(nQueries)(QueryPoint(pt(), rnd.nextInt(pixels), Vec3(rnd.nextDouble(), rnd.nextDouble(), rnd.nextDouble()), Vec3(0, 0, 1)))
    (PhotonMap.build(photons, box, f, h), QuerySet.build(queries, f))
  }

  for (f <- Seq(FloatFormat.fp32, FloatFormat.fp16, FloatFormat.fp64))
    test(s"render in $f equals brute force over all photons, for 1 and 2 threads alike") {
      val pixels = 50
      val (map, queries) = randomScene(f.width, 3000, 2000, pixels, f, 9.0)
      val arith = ShadeArith.rounded(f)
      val r1 = Render.run(map, queries, pixels, arith, threads = 1)
      val r2 = Render.run(map, queries, pixels, arith, threads = 2)
      assert(r1.rgb.toSeq == r2.rgb.toSeq && r1.stats == r2.stats)
      val list = Render.shaderOps(map, queries, arith)
      assert(list.stats == r1.stats)
      // brute force: every (query, photon) pair whose cond holds, with no tree at all
      val want = new Array[Double](3 * pixels)
      var passing = 0L
      for (q <- 0 until queries.size; i <- 0 until map.size
           if arith.cond(queries.qx(q), queries.qy(q), queries.qz(q), map.px(i), map.py(i), map.pz(i), map.h)) {
        passing += 1
        for (c <- 0 until 3)
          want(3 * queries.pixel(q) + c) += f.decode(arith.color(map.kernel(i), map.brdf(i), map.h, map.power(c)(i), queries.contribution(c)(q)))
      }
      assert(passing == r1.stats.shaderOpsPassing && passing > 1000)
      for (k <- want.indices) assert(math.abs(r1.rgb(k) - want(k)) <= 1e-12 * math.abs(want(k)), s"pixel value $k")
      assert(r1.stats.queries == 2000 && r1.stats.photons == 3000 && r1.stats.treeDepth == 12)
      assert(r1.stats.shaderOps > passing && r1.stats.treeSearchOps > 2000)
    }

  test("mismatched formats and pixels outside the image are errors") {
    val (map, queries) = randomScene(1, 50, 20, 10, FloatFormat.fp32, 5.0)
    assert(intercept[MapmError](Render.run(map, queries, 5, ShadeArith.rounded(FloatFormat.fp32))).getMessage.contains("outside an image"))
    assert(intercept[MapmError](Render.run(map, queries, 10, ShadeArith.rounded(FloatFormat.fp16))).getMessage.contains("one format"))
    assert(intercept[MapmError](PhotonMap.build(Array.empty[Photon], Box(Vec3.zero, Vec3.one), FloatFormat.fp16, 300.0))
      .getMessage.contains("h^2 overflows"))
  }

  test("quantizing queries and photons: values a format cannot carry are one MapmError naming them") {
    val f = FloatFormat.fp16
    def q(pos: Vec3, c: Vec3, pixel: Int = 0) = QueryPoint(pos, pixel, c, Vec3(0, 1, 0))
    def err(body: => Any) = intercept[MapmError](body).getMessage
    val ok = q(Vec3(1, 2, 3), Vec3(0.5, 0.25, 1))
    assert(err(QuerySet.build(Array(ok, q(Vec3(1, 1e6, 3), Vec3.one)), f)).contains("query 1 y coordinate = 1.00000e+06 overflows format fp16"))
    assert(err(QuerySet.build(Array(q(Vec3(Double.NaN, 0, 0), Vec3.one)), f)).contains("query 0 x coordinate is NaN"))
    assert(err(QuerySet.build(Array(ok, ok, q(Vec3.one, Vec3(0.5, -0.1, 0))), f)).contains("query 2: contribution"))
    assert(err(QuerySet.build(Array(q(Vec3.one, Vec3(1e9, 0, 0))), f)).contains("query 0 contribution"))
    assert(err(QuerySet.build(Array(q(Vec3.one, Vec3.one, -3)), f)).contains("pixel index -3 is negative"))
    val built = QuerySet.build(Array(ok, q(Vec3(4, 5, 6), Vec3(0, 1, 0.125), 7)), f)
    assert(built.qy.toSeq == Seq(f.encode(2.0), f.encode(5.0)) && built.pixel.toSeq == Seq(0, 7) && built.z.toSeq == Seq(3.0, 6.0))
    assert(built.contribution(2).toSeq == Seq(f.encode(1.0), f.encode(0.125)))
    val box = Box(Vec3.zero, Vec3(1e6, 1e6, 1e6))
    def ph(pos: Vec3, power: Vec3) = Photon(pos, power, Vec3(0, -1, 0), Vec3(0, 1, 0))
    assert(err(PhotonMap.build(Array(ph(Vec3(1, 1, 1), Vec3.one), ph(Vec3(2, 2, 1e5), Vec3.one)), box, f, 1.0)).contains("photon 1 z coordinate = 100000 overflows format fp16"))
    assert(err(PhotonMap.build(Array(ph(Vec3(1, 1, 1), Vec3(1, -1, 1))), box, f, 1.0)).contains("power (1.0, -1.0, 1.0) must be non-negative"))
    assert(err(PhotonMap.build(Array(ph(Vec3(1, 1, 1), Vec3(1, 1, 1e7))), box, f, 1.0)).contains("photon 0 power"))
  }
}
