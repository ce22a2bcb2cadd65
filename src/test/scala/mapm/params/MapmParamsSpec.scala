package mapm.params

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

  test("SOP L1 banks: one per SOA, never more than Table 4.2's 64 KiB per SOM") {
    def bank(a: Int) = MapmParams.table48(4, 4, a).sopL1Bank
    assert(bank(1).sizeBytes == 65536 && bank(2).sizeBytes == 32768 && bank(3).sizeBytes == 16384 && bank(4).sizeBytes == 16384)
    assert((1 to 8).forall(a => a * bank(a).sizeBytes <= 65536))
    assert(MapmParams.table48(4, 4, 3).rsPerSoa == 8)
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
    assert(msg(MapmParams(queues = QueueParams(registerQueueDepth = 25))).contains("Register queue depth 25 must exceed the tree-depth reserve"))
    assert(msg(MapmParams(counts = ModuleCounts(1, 1, 3), queues = QueueParams(rsEntries = 8))).contains("reservation-station entries 8"))
    assert(msg(QueueParams(queryFetches = 65)).contains("query fetches"))
    assert(MapmParams.table48(64, 64, 4).queues.rsEntries == 32)
    val e = intercept[mapm.MapmError](MapmParams.of(2, 2, 2, FloatFormat.fp32, 3, registerQueueDepth = Some(10)))
    assert(e.getMessage.startsWith("configuration 2/2/2 e8m23: Register queue depth must be 8..4096") ||
      e.getMessage.startsWith("configuration 2/2/2 e8m23: Register queue depth 10"), e.getMessage)
  }
}
