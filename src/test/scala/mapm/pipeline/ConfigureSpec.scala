package mapm.pipeline

import mapm.numerics.FloatFormat
import mapm.params._
import org.scalatest.funsuite.AnyFunSuite

/** A configuration as a command line asks for it ([[Configure.of]]): cache geometries
  * (`SIZE[/LINE[/WAYS]]`) and the sizes it overrides, reaching the parameters or refused naming
  * their option. */
class ConfigureSpec extends AnyFunSuite {
  test("cache geometry from the command line: SIZE[/LINE[/WAYS]], parts left out keep the default's") {
    assert(CacheSpec.parse("32K/32/4") == CacheSpec(Some(32768), Some(32), Some(4)))
    assert(CacheSpec.parse("1M") == CacheSpec(Some(1 << 20)))
    assert(CacheSpec.parse("512/16") == CacheSpec(Some(512), Some(16)))
    assert(CacheSpec.parse("128K/64/full").ways.contains(CacheSpec.Full))
    val d = CachesParams()
    assert(CacheSpec.parse("8K").applyTo(d.tsL1) == CacheParams(8192, 32, 2), "set-associative stays 2-way")
    assert(CacheSpec.parse("128K").applyTo(d.tsL2) == CacheParams(131072, 64, 2048), "fully associative stays fully associative")
    assert(CacheSpec.parse("64K/32/full").applyTo(d.sopL1).fullyAssociative)
    for ((bad, why) <- Seq("abc" -> "'abc' is not a positive byte count", "0" -> "'0' is not a positive byte count",
        "16K/x" -> "'x' is not a positive byte count", "16K/32/0" -> "ways '0' is not a count", "1/2/3/4" -> "too many parts"))
      assert(intercept[mapm.MapmError](CacheSpec.parse(bad)).getMessage.contains(why), bad)
  }

  test("tuning overrides reach the configuration; a broken geometry names its option") {
    val t = Tuning(registerQueueDepth = Some(64), rsEntries = Some(24), tsL1 = CacheSpec.parse("4K/32/1"),
      sopL2 = CacheSpec.parse("128K"), memOutstanding = Some(16))
    val p = Configure.of(4, 4, 3, FloatFormat.fp32, 3, tuning = t)
    assert(p.queues.registerQueueDepth == 64 && p.queues.rsEntries == 24 && p.memory.maxOutstanding == 16)
    assert(p.caches.tsL1 == CacheParams(4096, 32, 1) && p.caches.sopL2 == CacheParams(131072, 64, 2048))
    assert(p.caches.soq == MapmParams.default.caches.soq, "the rest as the hierarchy gives it")
    assert(t.describe == Seq("rq-depth=64", "rs-entries=24", "ts-l1=4096/32/1", "sop-l2=131072", "mem-outstanding=16"))
    // a default line grows to fit a record; a line the user gives is checked as given
    assert(Configure.of(1, 1, 1, FloatFormat.fp64, 3).caches.sopL1.lineBytes == 64)
    val e = intercept[mapm.MapmError](Configure.of(1, 1, 1, FloatFormat.fp64, 3, tuning = Tuning(sopL1 = CacheSpec.parse("64K/32/2"))))
    assert(e.getMessage.contains("SOP L1 line of 32 bytes is shorter than a 64-byte photon record"), e.getMessage)
    val f = intercept[mapm.MapmError](Configure.of(1, 1, 1, FloatFormat.fp32, 3, tuning = Tuning(tsL1 = CacheSpec.parse("15K"))))
    assert(f.getMessage == "configuration 1/1/1 e8m23: --ts-l1: cache set count must be a power of two, got 120 (size 15360, line 64, ways 2)", f.getMessage)
  }

  test("--sop-l2-banks: 1 is the shared SOP L2, a power of two up to 64 banks; anything else a one-line error naming it") {
    def banks(n: Int) = Configure.of(2, 2, 2, FloatFormat.fp32, 3, tuning = Tuning(sopL2Banks = Some(n)))
    def tsBanks(n: Int) = Configure.of(2, 2, 2, FloatFormat.fp32, 3, tuning = Tuning(tsL2Banks = Some(n)))
    // 2/2/2 has four SOP L1 banks, so the scalable hierarchy gives it two SOP L2 banks; 1 shares it
    assert(banks(1).uncore.sopL2 == L2Structure.Shared && banks(2) == Configure.of(2, 2, 2, FloatFormat.fp32, 3))
    for (n <- Seq(2, 4, 8, 16, 32, 64)) {
      val p = banks(n)
      assert(p.uncore.sopL2 == L2Structure.Banked(n) && p.name.contains(s"_b$n"))
      // Table 4.2's 512 KiB fully associative SOP L2 of 64-byte lines, split evenly.
      assert(p.sopL2Bank == CacheParams(524288 / n, 64, 8192 / n))
    }
    assert(Tuning(sopL2Banks = Some(8)).describe == Seq("sop-l2-banks=8"))
    for (n <- Seq(0, 3, 12, 128))
      assert(intercept[mapm.MapmError](banks(n)).getMessage == s"--sop-l2-banks: L2 banks must be a power of two 2..64, got $n")
    // The TS L2 the same way: Table 4.2's 256 KiB fully associative TS L2 split evenly.
    assert(tsBanks(4).uncore.tsL2 == L2Structure.Banked(4) && tsBanks(4).tsL2Bank == CacheParams(65536, 64, 1024) && tsBanks(4).name.contains("_tb4"))
    assert(intercept[mapm.MapmError](tsBanks(6)).getMessage == "--ts-l2-banks: L2 banks must be a power of two 2..64, got 6")
    // A set-associative SOP L2 needs a set per bank.
    val few = intercept[mapm.MapmError](Configure.of(1, 1, 1, FloatFormat.fp32, 3,
      tuning = Tuning(sopL2 = CacheSpec.parse("4K/64/16"), sopL2Banks = Some(8))))
    assert(few.getMessage.contains("cannot be split into 8 banks"), few.getMessage)
  }

  test("--so-bus: the ring with the scalable hierarchy, serial with Table 4.2's; the ring brings two more reservation-station entries a SOA unless --rs-entries says") {
    import mapm.params.{Hierarchy, SoBus}
    val ring = Configure.of(16, 16, 2, FloatFormat.fp32, 3)
    assert(ring.uncore.soBus == SoBus.Ring && ring.queues.rsEntries == 20 && ring.rsPerSoa == 10)
    val serial = Configure.of(16, 16, 2, FloatFormat.fp32, 3, tuning = Tuning(soBus = Some(SoBus.Serial)))
    assert(serial.uncore.soBus == SoBus.Serial && serial.queues.rsEntries == 16)
    val table42 = Configure.of(16, 16, 2, FloatFormat.fp32, 3, tuning = Tuning(hierarchy = Hierarchy.Table42))
    assert(table42.uncore.soBus == SoBus.Serial && table42.queues.rsEntries == 16)
    assert(Configure.of(16, 16, 2, FloatFormat.fp32, 3, tuning = Tuning(hierarchy = Hierarchy.Table42, soBus = Some(SoBus.Ring))).queues.rsEntries == 20)
    assert(Configure.of(3, 2, 3, FloatFormat.fp32, 3).rsPerSoa == 10)
    assert(Configure.of(16, 16, 2, FloatFormat.fp32, 3, tuning = Tuning(rsEntries = Some(16))).queues.rsEntries == 16)
    assert(ring.name.endsWith("_ring") && !serial.name.contains("ring"))
  }
}

