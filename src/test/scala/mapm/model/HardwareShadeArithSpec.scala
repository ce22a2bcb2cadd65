package mapm.model

import mapm.numerics._

import mapm.Slow
import mapm.testutil.ShaderCases
import org.scalatest.funsuite.AnyFunSuite

/** ShadeArith.hardware against the models it must equal bit for bit (ShaderChainModel for colour
  * and flags, CondModel for cond), its cond shortcut bounds against exact arithmetic, and the
  * render and shader-op list built on it. */
@Slow
class HardwareShadeArithSpec extends AnyFunSuite {
  private val configs = Seq(FloatFormat.fp32 -> 3, FloatFormat.fp32 -> 0, FloatFormat.fp16 -> 3)

  for ((f, g) <- configs)
    test(s"$f g = $g: color, shade and shadeFlags equal ShaderChainModel per channel, on 4 threads at once") {
      val arith = ShadeArith.hardware(f, g)
      val chain = new ShaderChainModel(f, g)
      val cases = new ShaderCases(f, seed = 7 + g)
      // Operations in runs that share kernel, BRDF and h (the cache hits) and change them (misses).
      var shared = cases.operation()
      // Powers and contributions from small pools too, as in a rendered scene (the table of
      // finished channels hits), and fresh ones (it misses, or a slot is replaced).
      val pool = Array.fill(40)(cases.operation())
      val rnd = new scala.util.Random(11 + g)
      val ops = Array.tabulate(20000) { k =>
        val op = cases.operation()
        if (k % 7 == 0) shared = op
        if (k % 3 != 0) { op(0) = shared(0); op(1) = shared(1); op(2) = shared(2) }
        if (k % 2 == 0) for (c <- 3 until 9) op(c) = pool(rnd.nextInt(pool.length))(c)
        op
      }
      val want = ops.map(op => Array.tabulate(3)(c => chain.colour(op(0), op(1), op(2), op(3 + c), op(6 + c))))
      val bad = new java.util.concurrent.atomic.AtomicInteger(0)
      val threads = Array.tabulate(4)(t => new Thread(() => {
        val out = new Array[Long](3); val flags = new Array[Int](3); val out2 = new Array[Long](3)
        val values = new Array[Double](3); val scratch = new Array[Long](3)
        for (k <- (t until ops.length by 4) ++ (0 until ops.length by 5)) {
          val o = ops(k)
          arith.shadeFlags(o(0), o(1), o(2), o(3), o(4), o(5), o(6), o(7), o(8), out, flags)
          arith.shade(o(0), o(1), o(2), o(3), o(4), o(5), o(6), o(7), o(8), out2)
          arith.shadeValues(o(0), o(1), o(2), o(3), o(4), o(5), o(6), o(7), o(8), scratch, values)
          for (c <- 0 until 3) {
            val w = want(k)(c)
            val v = f.decode(w.bits)
            val valueOk = java.lang.Double.doubleToRawLongBits(values(c)) == java.lang.Double.doubleToRawLongBits(v) || (v.isNaN && values(c).isNaN)
            if (out(c) != w.bits || flags(c) != w.flags || out2(c) != w.bits || !valueOk ||
              arith.color(o(0), o(1), o(2), o(3 + c), o(6 + c)) != w.bits) bad.incrementAndGet()
          }
        }
      }))
      threads.foreach(_.start()); threads.foreach(_.join())
      assert(bad.get == 0, s"${bad.get} channel mismatches")
      assert(arith.hasFlags && want.exists(_.exists(_.flags != 0)) == (f == FloatFormat.fp16))
    }

  for (f <- Seq(FloatFormat.fp32, FloatFormat.fp16))
    test(s"$f: cond equals CondModel, and condClearBounds only decides cases the exact d2 settles") {
      val arith = ShadeArith.hardware(f, 3)
      val gen = new CondGen(f, seed = f.width)
      var below = 0; var above = 0
      for (_ <- 0 until 100000) {
        val v = gen.next()
        val cond = arith.cond(v(0), v(1), v(2), v(3), v(4), v(5), v(6))
        assert(cond == CondModel.cond(f, v(0), v(1), v(2), v(3), v(4), v(5), v(6)))
        val d = v.map(f.decode)
        if (d.forall(x => !x.isNaN && !x.isInfinite)) {
          val (lo, hi) = arith.condClearBounds(v(6))
          val d2 = (0 until 3).map(i => BigDecimal(d(i)) - BigDecimal(d(3 + i))).map(x => x * x).sum
          if (!lo.isInfinite && d2 < BigDecimal(lo)) { below += 1; assert(cond, s"d2 $d2 < lo $lo but cond false: ${v.map(f.hex).mkString(",")}") }
          if (!hi.isInfinite && d2 > BigDecimal(hi)) { above += 1; assert(!cond, s"d2 $d2 > hi $hi but cond true: ${v.map(f.hex).mkString(",")}") }
        }
      }
      info(s"$below cases decided true by the bounds, $above false")
      assert(below > 1000 && above > 1000)
    }

  private def scene(f: FloatFormat, seed: Int, nPhotons: Int, nQueries: Int, pixels: Int, h: Double) = {
    val rnd = new scala.util.Random(seed)
    val box = Box(Vec3(0, 0, 0), Vec3(100, 80, 120))
    def pt() = Vec3(rnd.nextDouble() * 100, rnd.nextDouble() * 80, rnd.nextDouble() * 120)
    val photons = Array.fill(nPhotons)(Photon(pt(), Vec3(rnd.nextDouble(), rnd.nextDouble(), rnd.nextDouble()), Vec3(0, -1, 0), Vec3(0, 1, 0)))
    val queries = Array.fill(nQueries)(QueryPoint(pt(), rnd.nextInt(pixels), Vec3(rnd.nextDouble(), rnd.nextDouble(), rnd.nextDouble()), Vec3(0, 0, 1)))
    (PhotonMap.build(photons, box, f, h), QuerySet.build(queries, f))
  }

  for (f <- Seq(FloatFormat.fp32, FloatFormat.fp16))
    test(s"$f: shader-op list (1 and 3 threads alike) and render equal the models applied to every SO") {
      val pixels = 40
      val (map, queries) = scene(f, f.width, 2000, 1500, pixels, 10.0)
      val arith = ShadeArith.hardware(f, 3)
      val chain = new ShaderChainModel(f, 3)
      val list = Render.shaderOps(map, queries, arith, threads = 3)
      val one = Render.shaderOps(map, queries, arith)
      assert(list.query.toSeq == one.query.toSeq && list.node.toSeq == one.node.toSeq && list.cond.toSeq == one.cond.toSeq)
      val flags = list.flags.get
      for (c <- 0 until 3) assert(list.color(c).toSeq == one.color(c).toSeq && flags(c).toSeq == one.flags.get(c).toSeq)
      val want = new Array[Double](3 * pixels)
      for (k <- 0 until list.size) {
        val (q, i) = (list.query(k), list.node(k))
        val cond = CondModel.cond(f, queries.qx(q), queries.qy(q), queries.qz(q), map.px(i), map.py(i), map.pz(i), map.h)
        assert(list.cond(k) == cond, s"SO $k")
        for (c <- 0 until 3) {
          val r = chain.colour(map.kernel(i), map.brdf(i), map.h, map.power(c)(i), queries.contribution(c)(q))
          assert(list.color(c)(k) == r.bits && flags(c)(k) == r.flags, s"SO $k channel $c")
          if (cond) want(3 * queries.pixel(q) + c) += f.decode(r.bits)
        }
      }
      val run = Render.run(map, queries, pixels, arith, threads = 2)
      assert(run.stats == list.stats && list.stats.shaderOpsPassing > 1000 && list.size > list.stats.shaderOpsPassing)
      for (k <- want.indices) assert(math.abs(run.rgb(k) - want(k)) <= 1e-12 * math.abs(want(k)), s"pixel value $k")
      assert(Render.shaderOps(map, queries, ShadeArith.rounded(f)).flags.isEmpty)
    }
}
