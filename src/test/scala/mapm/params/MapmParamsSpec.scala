package mapm.params

import mapm.pipeline.{Configure, Tuning}

import mapm.numerics.FloatFormat
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
    assert(MapmParams.default.name == "t16s16a2_e8m23_g3_b16_ring" && MapmParams.dissertation.name == "t16s16a2_e8m23_g3")
    // A lighter stage weight deepens the cond check's units (FpuDepth.of: fp32 at 1.0 per stage).
    val deep = MapmParams(numbers = NumberParams(fpuStageWeight = 1.0))
    assert(mapm.fpu.FpuDepth.of(FloatFormat.fp32, deep.numbers.fpuStageWeight) == mapm.fpu.FpuDepth(11, 14, 1, 33))
    assert(deep.name == "t16s16a2_e8m23_g3_fw1" && MapmParams(numbers = NumberParams(fpuStageWeight = 1.5)).name.endsWith("_fw1p5"))
  }

  test("presets: the default is the dissertation's MAPM with the scalable hierarchy, and the small one is what the command line's 1/1/1 gives") {
    // Table 4.8's 16/16/2 with 8 reservation-station entries per SOA is the dissertation's MAPM (section 4.1).
    assert(MapmParams.dissertation == MapmParams.presets("16/16/2"))
    assert(MapmParams.default == MapmParams.dissertation.copy(uncore = UncoreParams(sopL2 = L2Structure.Banked(16), soBus = SoBus.Ring),
      queues = MapmParams.dissertation.queues.copy(rsEntries = 20),
      caches = MapmParams.dissertation.caches.copy(soq = CacheParams(16384, 32, 4), tsL1 = CacheParams(16384, 64, 2))))
    assert(Configure.of(16, 16, 2, FloatFormat.fp32, 3) == MapmParams.default)
    assert(Configure.of(16, 16, 2, FloatFormat.fp32, 3, tuning = Tuning(hierarchy = Hierarchy.Table42)) == MapmParams.dissertation)
    assert(MapmParams.dissertation.counts == ModuleCounts(16, 16, 2) && MapmParams.dissertation.queues.rsEntries == 16)
    val s = MapmParams.small
    assert(s.counts == ModuleCounts(1, 1, 1) && s.name == "t1s1a1_e8m23_g3_ring" && s.rsPerSoa == 10)
    assert(s.caches == MapmParams.default.caches && s.numbers == MapmParams.dissertation.numbers && s.uncore == UncoreParams(soBus = SoBus.Ring))
    assert(Configure.of(1, 1, 1, FloatFormat.fp32, 3) == s)
  }

  test("slots, record sizes and cache lines follow the format and the layout") {
    import mapm.format.SlotLayout.{Packed, Wide}
    // (format, layout) -> (slot, node, photon, SOQ word, SOP L1 line) as docs/memory-layout.md gives them
    for (((f, layout), (slot, node, photon, soqWord, sopLine)) <- Seq(
           (FloatFormat.fp16, Packed) -> (2, 8, 16, 16, 32), (FloatFormat.fp16, Wide) -> (4, 8, 32, 32, 32),
           (FloatFormat.bf16, Packed) -> (2, 8, 16, 16, 32), (FloatFormat(6, 9), Packed) -> (2, 8, 16, 16, 32),
           (FloatFormat.fp32, Packed) -> (4, 8, 32, 32, 32), (FloatFormat.fp24, Wide) -> (4, 8, 32, 32, 32),
           (FloatFormat(10, 40), Packed) -> (8, 16, 64, 64, 64), (FloatFormat.fp64, Wide) -> (8, 16, 64, 64, 64))) {
      val p = Configure.of(4, 4, 2, f, 3, layout = layout)
      assert(p.slotBytes == slot && p.records.node.bytes == node && p.records.photon.bytes == photon && p.records.queryHwBytes == soqWord, s"$f $layout")
      // The SOQ line holds a whole query record: 64 bytes with 8-byte slots.
      assert(p.caches.sopL1.lineBytes == sopLine && p.caches.tsL1.lineBytes == 64 && p.caches.soq.lineBytes == (soqWord max 32), s"$f $layout")
      assert(p.name.contains("_wide") == (layout == Wide && f.width <= 16), p.name)
    }
  }

  test("the scalable hierarchy: an SOP L2 bank per two SOP L1 banks (a power of two, at most 64, at most what the SOP L2 splits into), TS L1s of 64-byte lines") {
    val table42 = CachesParams().sopL2
    // (TSMs, SOMs, SOAs) -> banks: 32 SOP L1 banks -> 16; 48 -> 24 -> 16; 6 -> 3 -> 2; 3 -> 1 (shared); 1024 x 16 -> 64.
    for (((t, s, a), want) <- Seq((16, 16, 2) -> 16, (16, 16, 3) -> 16, (8, 8, 2) -> 8, (4, 4, 2) -> 4, (2, 3, 2) -> 2, (2, 1, 3) -> 1,
                                  (1, 1, 1) -> 1, (1024, 1024, 16) -> 64))
      assert(Hierarchy.Scalable.sopL2Banks(ModuleCounts(t, s, a), table42) == want, s"$t/$s/$a")
    // A small set-associative SOP L2 caps the banks: 4 sets take 4 banks at most.
    assert(Hierarchy.Scalable.sopL2Banks(ModuleCounts(16, 16, 2), CacheParams(4096, 64, 16)) == 4)
    val p = Hierarchy.Scalable(MapmParams.table48(8, 8, 2))
    assert(p.uncore.sopL2 == L2Structure.Banked(8) && p.uncore.tsL2 == L2Structure.Shared && p.caches.soq.ways == 4)
    assert(p.caches.tsL1 == CacheParams(16384, 64, 2) && Hierarchy.Table42.tsL1 == CachesParams().tsL1)
    assert(Hierarchy.Table42(p) == MapmParams.table48(8, 8, 2))
  }

  test("impossible parameters are refused with a message naming them") {
    def msg(f: => Any): String = intercept[IllegalArgumentException](f).getMessage
    assert(msg(ModuleCounts(0, 1, 1)).contains("TSM count"))
    assert(msg(ModuleCounts(1, 1, 0)).contains("SOAs per SOM"))
    assert(msg(CacheParams(1000, 32, 1)).contains("multiple of the line size"))
    assert(msg(CacheParams(3 * 1024, 32, 1)).contains("power of two"))
    assert(msg(CacheParams(1024, 24, 1)).contains("cache line"))
    val fp64 = NumberParams(FloatFormat.fp64)
    assert(msg(MapmParams(numbers = fp64)).contains("SOQ line of 32 bytes is shorter than the 64 bytes of a query record it reads (8-byte slots)"))
    assert(msg(MapmParams(numbers = fp64, caches = CachesParams(soq = CacheParams(16 * 1024, 64, 1)))).contains("SOP L1 line of 32 bytes is shorter than a 64-byte photon record (8-byte slots)"))
    assert(msg(MapmParams(caches = CachesParams(tsL2 = CacheParams(256 * 1024, 128, 2048)))).contains("TS L2 line of 128 bytes is longer than the memory image's 64-byte array alignment"))
    assert(msg(MapmParams(queues = QueueParams(registerQueueDepth = 25))).contains("Register queue depth 25 must exceed the tree-depth reserve"))
    assert(msg(MapmParams(counts = ModuleCounts(1, 1, 3), queues = QueueParams(rsEntries = 8))).contains("reservation-station entries 8"))
    assert(msg(QueueParams(queryFetches = 65)).contains("query fetches"))
    assert(msg(NumberParams(fpuStageWeight = 0.25)).contains("FPU logic per stage must be 0.5..100"))
    assert(MapmParams.table48(64, 64, 4).queues.rsEntries == 32)
    val e = intercept[mapm.MapmError](Configure.of(2, 2, 2, FloatFormat.fp32, 3, tuning = Tuning(registerQueueDepth = Some(10))))
    assert(e.getMessage.startsWith("configuration 2/2/2 e8m23: Register queue depth must be 8..4096") ||
      e.getMessage.startsWith("configuration 2/2/2 e8m23: Register queue depth 10"), e.getMessage)
  }
}
