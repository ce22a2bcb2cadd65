package mapm.costflow

import java.nio.file.Files
import mapm.MapmError
import mapm.numerics.FloatFormat
import mapm.pipeline.{Configure, Tuning}
import mapm.sim.{EmitFiles, HarnessStats, MapmRtl}
import org.scalatest.funsuite.AnyFunSuite

/** The SRAM energy model (SramEnergy): its fit against the published figures it comes from, its
  * arrays against the memories firtool emitted for the same MAPM, and one frame's accesses
  * counted by hand. */
class SramEnergySpec extends AnyFunSuite {
  test("the access-energy fit stays within 15 % of Horowitz's three published SRAM reads; x16 to 0.18 um, 1.8 V") {
    // ISSCC 2014, "Computing's energy problem (and what we can do about it)": a 64-bit read of an
    // 8 KB SRAM costs 10 pJ, of 32 KB 20 pJ, of 1 MB 100 pJ (45 nm, 0.9 V).
    for ((kib, pj) <- Seq(8.0 -> 10.0, 32.0 -> 20.0, 1024.0 -> 100.0))
      assert(math.abs(SramEnergy.pj64At45nm(kib) / pj - 1) <= 0.15, s"$kib KB: ${SramEnergy.pj64At45nm(kib)} pJ against $pj")
    assert(math.abs(SramEnergy.ScaleTo180nm - 16.0) < 1e-12)
    // 8 KB as 1,024 rows of 64 bits, one row read: 10 pJ x 16.
    assert(math.abs(SramEnergy.accessPj(1024, 64, 64) - 160.0) < 1e-9)
    // Twice the bits from the same array cost twice; a 4x larger array costs twice per bit.
    assert(math.abs(SramEnergy.accessPj(1024, 64, 128) - 320.0) < 1e-9)
    assert(math.abs(SramEnergy.accessPj(4096, 64, 64) - 320.0) < 1e-9)
  }

  // Each (depth, width) with its instance count: from the model, and from the memory modules in
  // the SystemVerilog firtool emitted (each instance path counted).
  private def modelled(p: mapm.params.MapmParams): Map[(Long, Int), Int] =
    SramEnergy.arrays(p).groupBy(a => (a.depth, a.width)).map { case (k, as) => k -> as.map(_.instances).sum }
  private def emitted(p: mapm.params.MapmParams): Map[(Long, Int), Int] = {
    val (dir, top) = MapmRtl.emit(p)
    val sv = new String(Files.readAllBytes(dir.resolve(s"$top.sv")), "UTF-8")
    EmitFiles.read(sv, top).memories.groupBy(m => (m.depth, m.width)).map { case (k, ms) => k -> ms.map(_.instances.size).sum }
  }

  for (p <- Seq(Configure.of(1, 1, 1, FloatFormat.fp32, 3), Configure.of(3, 2, 3, FloatFormat.fp16, 2),
                Configure.of(2, 3, 2, FloatFormat.fp32, 3, tuning = Tuning(sopL2Banks = Some(8), tsL2Banks = Some(2)))))
    test(s"${p.name}: the model's arrays are the emitted memories, depth, width and instances") {
      val m = modelled(p)
      val e = emitted(p)
      assert(m == e, s"model $m, emitted $e")
    }

  test("one frame's accesses at 1/1/1, counted by hand from its counters") {
    val p = Configure.of(1, 1, 1, FloatFormat.fp32, 3)
    // 1,000 cycles, 500 SOs, 300 TS ops; every cache 900 hits and 100 misses, the SOQ 10 misses.
    val st = HarnessStats.parse(ujson.write(mapm.testutil.StatsFixture.json(cycles = 1000, so = 500, ts = 300, bytes = 4000, soqMisses = 10)), "fixture")
    val a = SramEnergy.arrays(p, st).map(x => x.name -> x).toMap
    // The SOP L1 (one bank): its tags read every one of the 1,000 cycles, written at each of its
    // 1,000 lookups; its data read at each lookup and written once per refill beat (one a line).
    val sopL1Beats = mapm.uncore.Shapes(p).sopL1.beatsPerLine
    assert(a("sopL1 tags").reads == 1000 && a("sopL1 tags").writes == 1000)
    assert(a("sopL1 data").reads == 1000 && a("sopL1 data").writes == 100 * sopL1Beats)
    // The SOQ: 910 lookups, 10 lines of two 16-byte beats each.
    assert(a("soq data").reads == 910 && a("soq data").writes == 20 && a("soq tags").writes == 910)
    // Two Register-queue banks, each read every cycle; one write per TS op.
    assert(a("Register queue").reads == 2000 && a("Register queue").writes == 300)
    val total = a.values.map(_.dynamicNj).sum
    assert(total > 0 && a.values.forall(_.dynamicNj >= 0))
    // Counters of a cache the configuration has, missing: one line naming it.
    val e = intercept[MapmError](SramEnergy.arrays(p, st.copy(caches = st.caches - "sopL2")))
    assert(e.getMessage.contains("sopL2"))
  }
}
