package mapm.top

import mapm.model.FloatFormat
import org.scalatest.funsuite.AnyFunSuite

class MapmParamsSpec extends AnyFunSuite {
  test("defaults are Table 4.2's cache geometry") {
    val c = MapmParams().caches
    assert((c.tsL1.sizeBytes, c.tsL1.lineBytes, c.tsL1.ways, c.tsL1.sets) == (16384, 32, 2, 256))
    assert(c.tsL2.fullyAssociative && c.tsL2.lines == 4096)
    assert(c.soq.ways == 1 && c.soq.lines == 512)
    assert((c.sopL1.sizeBytes, c.sopL1.ways) == (65536, 2))
    assert(c.sopL2.fullyAssociative && c.sopL2.lines == 8192)
  }

  test("Table 4.8 presets cover its 24 rows") {
    assert(MapmParams.presets.size == 24)
    assert(MapmParams.presets("16/16/3").counts == ModuleCounts(16, 16, 3))
    assert(MapmParams.default.name == "t16s16a2_e8m23_g3")
  }

  test("impossible parameters are refused with a message naming them") {
    def msg(f: => Any): String = intercept[IllegalArgumentException](f).getMessage
    assert(msg(ModuleCounts(0, 1, 1)).contains("TSM count"))
    assert(msg(ModuleCounts(1, 1, 0)).contains("SOAs per SOM"))
    assert(msg(CacheParams(1000, 32, 1)).contains("multiple of the line size"))
    assert(msg(CacheParams(3 * 1024, 32, 1)).contains("power of two"))
    assert(msg(CacheParams(1024, 24, 1)).contains("cache line"))
    assert(msg(NumberParams(FloatFormat.fp64)).contains("32-bit memory slots"))
    assert(msg(MapmParams(counts = ModuleCounts(64, 64, 4))).contains("Register queue depth"))
    assert(MapmParams.table48(64, 64, 4).queues.registerQueueDepth == 256)
  }
}
