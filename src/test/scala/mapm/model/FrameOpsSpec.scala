package mapm.model

import mapm.numerics._

import org.scalatest.funsuite.AnyFunSuite

/** FrameOps against the search-and-shade engine's own list of shader operations and operation
  * counts ([[Render.shaderOps]]) on a small Cornell frame. */
class FrameOpsSpec extends AnyFunSuite {
  private lazy val frame = {
    val dir = TestScenes.tempDir()
    val obj = TestScenes.cornellObj.toAbsolutePath.toString
    val scene = TestScenes.write(dir, "small.json",
      s"""{ "obj": "$obj", "camera": { "position": [278, 273, -530], "direction": [0, 0, 1], "up": [0, 1, 0], "fov": 39.3 },
         |  "lights": [ { "type": "point", "position": [278, 540, 279], "power": [10000000, 10000000, 10000000] } ],
         |  "width": 8, "height": 6, "finalGatherRays": 4, "photons": 300, "maxBounces": 4, "seed": 3,
         |  "directLightSamples": 0 }""".stripMargin)
    Frame.prepare(SceneConfig.load(scene), FloatFormat.fp32, 1)
  }

  test("shader operations: the engine's (query, photon) pairs in order, with the photon's and query's values") {
    val list = Render.shaderOps(frame.map, frame.querySet, ShadeArith.hardware(FloatFormat.fp32, 3))
    assert(list.size > 100, "the frame has shader operations to compare")
    val ops = FrameOps.shaderOps(frame.map, frame.querySet, Int.MaxValue)
    assert(ops.size == list.size)
    val m = frame.map; val qs = frame.querySet
    for (k <- ops.indices) {
      val (q, i) = (list.query(k), list.node(k))
      val want = Seq(m.kernel(i), m.brdf(i), m.h, m.power(0)(i), m.power(1)(i), m.power(2)(i), qs.contribution(0)(q),
        qs.contribution(1)(q), qs.contribution(2)(q), qs.qx(q), qs.qy(q), qs.qz(q), m.px(i), m.py(i), m.pz(i))
      assert(ops(k).inputs.toSeq == want, s"operation $k")
    }
    assert(FrameOps.shaderOps(frame.map, frame.querySet, 17).map(_.inputs.toSeq) == ops.take(17).map(_.inputs.toSeq))
  }

  test("tree-search operations: as many as the engine counts; each compares the query's coordinate on the node's axis") {
    val list = Render.shaderOps(frame.map, frame.querySet, ShadeArith.hardware(FloatFormat.fp32, 3))
    val ts = FrameOps.treeSearchOps(frame.map, frame.querySet, Int.MaxValue)
    assert(ts.size.toLong == list.stats.treeSearchOps)
    assert(ts.forall(_.h == frame.map.h))
    val qs = frame.querySet
    val coords = (0 until qs.size).flatMap(q => Seq(qs.qx(q), qs.qy(q), qs.qz(q))).toSet
    val splits = frame.map.split.toSet
    assert(ts.forall(t => coords.contains(t.p) && splits.contains(t.s)))
    // The first search starts at the root: its first operation compares with the root's split.
    assert(ts.head.s == frame.map.split(0))
    assert(FrameOps.treeSearchOps(frame.map, frame.querySet, 5) == ts.take(5))
  }
}
