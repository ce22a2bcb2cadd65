package mapm.top

import mapm.pipeline._

import java.nio.file.{Files, Path, Paths}

import mapm.Slow
import mapm.pipeline.RtlRun
import mapm.format.{MemoryImage, SlotLayout}
import mapm.model.TestScenes
import mapm.numerics.{Arith, FloatFormat}
import mapm.params._
import mapm.sim.{Harness, HarnessStats}
import org.scalatest.funsuite.AnyFunSuite
import scala.jdk.CollectionConverters._

/** The whole MAPM's emitted SystemVerilog (the CIRCT output `emit` writes) in the Verilator
  * harness, against the model: every shader operation's (query, photon, colour bits, flags, cond)
  * checked by the harness as it leaves (none unexpected, none twice, none missing), the frame
  * bit-equal to the model's, the TS-op count equal to the model's. Memory latency is random per
  * request (0 to 300 cycles), responses come back in random order with random gaps, requests are
  * refused at random and the query stream has random gaps; the harness's idle watchdog fails a
  * run that stops making progress.
  *
  * Needs Verilator (cancels without it). Each configuration is verilated once and cached. */
@Slow
class MapmRtlSpec extends AnyFunSuite {
  private def haveVerilator: Boolean =
    mapm.testutil.HostTools.onPath("verilator")

  private val dir = Paths.get("target/mapm-rtl-test")

  /** A Cornell-box scene file: `w` x `h` pixels, `rays` final-gather rays, `photons` photons,
    * kernel radius `radius` (a JSON value: a number or {"auto": n}). */
  private def scene(name: String, w: Int, h: Int, rays: Int, photons: Int, radius: String, seed: Int = 5): Path = {
    Files.createDirectories(dir)
    val obj = TestScenes.cornellObj.toAbsolutePath.toString
    val text =
      s"""{ "obj": "$obj",
         |  "camera": { "position": [278, 273, -530], "direction": [0, 0, 1], "up": [0, 1, 0], "fov": 39.3 },
         |  "lights": [ { "type": "point", "position": [1, 25, 1], "power": [10000000, 10000000, 10000000] } ],
         |  "width": $w, "height": $h, "finalGatherRays": $rays, "photons": $photons, "maxBounces": 4,
         |  "h": $radius, "seed": $seed, "directLightSamples": 0 }""".stripMargin
    Files.write(dir.resolve(s"$name.json"), text.getBytes("UTF-8"))
  }

  private val stress = Harness.RunOptions(latency = 0, latencyMax = 300, queryGap = 0.3, reqStall = 0.2, respGap = 0.2,
    maxCycles = 5000000)

  /** Runs `p` on the prepared frame under `opts` with seeds `seeds`; returns the stats of each run. */
  private def check(prep: RtlRun.Prepared, p: MapmParams, opts: Harness.RunOptions, seeds: Seq[Long]): Seq[HarnessStats] =
    seeds.map { seed =>
      val run = RtlRun.runConfig(prep, p, opts.copy(seed = seed), dir.resolve(s"${prep.name}-${p.name}-$seed"), _ => ())
      assert(run.passed, s"${p.counts.label} ${p.numbers.format} seed $seed: ${run.failure}")
      val s = run.outcome.stats.get
      assert(s.soIssued == prep.model.count && s.soPassingCond == prep.model.passing)
      assert(s.tsOps.contains(prep.model.tsOps))
      assert(s.counters("soIssued") == prep.model.count, "the SO counter counts every SO into an SOA")
      assert(s.counters("rqPeak") <= p.queues.registerQueueDepth)
      s
    }

  private lazy val small = RtlRun.prepare(scene("small", 6, 5, 3, 64, """{ "auto": 12 }""").toString, Some(FloatFormat.fp32), 3, dir.toString, 2)
  private lazy val large = RtlRun.prepare(scene("large", 8, 6, 4, 1000, """{ "auto": 20 }""").toString, Some(FloatFormat.fp32), 3, dir.toString, 2)

  for (((t, s, a), seeds) <- Seq((1, 1, 1) -> Seq(1L, 2L, 3L), (2, 1, 2) -> Seq(4L, 5L, 6L), (4, 4, 2) -> Seq(7L, 8L), (3, 2, 3) -> Seq(9L, 10L)))
    test(s"$t/$s/$a fp32, 64 and 1,000 photons, random latency 0-300, reordering, gaps: every SO exact, none lost or twice") {
      assume(haveVerilator, "verilator is not on PATH")
      val p = Configure.of(t, s, a, FloatFormat.fp32, 3)
      assert(small.model.count > 100 && large.model.count > 1000)
      check(small, p, stress, seeds)
      check(large, p, stress, seeds.take(1))
      info(s"${seeds.size + 1} runs: ${small.frame.querySet.size} and ${large.frame.querySet.size} queries, ${small.model.count} and ${large.model.count} SOs")
    }

  test("SOP L2 in 4 banks at 3/3/3 (nine SOP L1 banks, an odd SOM count): every SO exact under random memory timing") {
    assume(haveVerilator, "verilator is not on PATH")
    val p = Configure.of(3, 3, 3, FloatFormat.fp32, 3, tuning = mapm.pipeline.Tuning(sopL2Banks = Some(4)))
    assert(p.uncore.sopL2 == L2Structure.Banked(4) && p.name.contains("_b4"))
    val stats = check(small, p, stress, Seq(21L, 22L)) ++ check(large, p, stress, Seq(23L))
    // Every SOP L1 miss reached the L2 banks: their accesses are the L1 misses.
    for (s <- stats) assert(s.counters("sopL2_hits") + s.counters("sopL2_misses") == s.counters("sopL1_misses"))
    info(s"bank-conflict waits: ${stats.map(_.counters("sopL2_conflicts")).mkString(", ")} requester-cycles")
  }

  /** Runs `p` on `prep` under the stress options with `seed`, recording every result beat:
    * (stats, the `cycle port q photon` lines in the order they came out, the verdict). */
  private def resultBeats(prep: RtlRun.Prepared, p: MapmParams, seed: Long): (HarnessStats, Seq[String], String) = {
    val out = dir.resolve(s"${prep.name}-${p.name}-results-$seed")
    val results = out.resolve("results.txt")
    val r = RtlRun.runConfig(prep, p, stress.copy(seed = seed, results = Some(results)), out, _ => ())
    assert(r.passed, s"${p.name} on ${prep.name}: ${r.failure}")
    (r.outcome.stats.get, Files.readAllLines(results).asScala.toSeq, r.outcome.verdict)
  }

  // Clock gating (docs/mapm.md, docs/soa.md): with every SOA, and every register inside it, clocked
  // in every cycle instead, the same frame under the same memory seed gives the same result beats
  // (cycle, port, q, photon), the same cycles and every counter equal; the harness checks every
  // colour in both runs.
  test("2/1/2 fp32 SOA and stage clock gating: beat for beat and counter for counter the ungated RTL on two scenes") {
    assume(haveVerilator, "verilator is not on PATH")
    val gated = Configure.of(2, 1, 2, FloatFormat.fp32, 3)
    val ungated = Configure.of(2, 1, 2, FloatFormat.fp32, 3, tuning = Tuning(soaClockGate = false, soaStageGate = false))
    assert(gated.clocking.soaClockGate && gated.clocking.soaStageGate && !ungated.clocking.soaClockGate &&
      !ungated.clocking.soaStageGate && ungated.name == gated.name.replace("_ring", "_nocg_nsg_ring"))
    for (prep <- Seq(small, large)) {
      val (gs, gr, _) = resultBeats(prep, gated, 41L)
      val (us, ur, _) = resultBeats(prep, ungated, 41L)
      assert(gr.size == prep.model.count && gr.nonEmpty)
      assert(gr == ur, s"${prep.name}: result beats differ, first at ${gr.zip(ur).indexWhere(x => x._1 != x._2)}")
      assert(gs.cycles == us.cycles && gs.counters == us.counters)
      assert(gs.stallCycles == us.stallCycles && gs.caches == us.caches && gs.bytesFetched == us.bytesFetched)
      info(s"${prep.name}: ${gs.cycles} cycles, ${gr.size} result beats identical")
    }
  }

  // The timing model (--fidelity timing): each SOA a delay line of its latency. Against the full RTL
  // on the same frame and the same memory seed: the same cycles, every counter but soPassed (which
  // counts cond bits the model does not compute) equal, the same stalls, cache and memory figures,
  // and the identical sequence of (cycle, port, q, photon) result beats.
  // Two configurations here (and 2/2/2 in MapmCoprocSpec): several SOMs, an odd SOA count, banked L2s.
  for (((t, s, a), seed) <- Seq((4, 4, 2) -> 33L, (3, 2, 3) -> 34L))
    test(s"$t/$s/$a fp32 timing model: cycle for cycle the full RTL's results, counters and stalls on two scenes") {
      assume(haveVerilator, "verilator is not on PATH")
      val full = Configure.of(t, s, a, FloatFormat.fp32, 3)
      val timing = Configure.of(t, s, a, FloatFormat.fp32, 3, fidelity = Fidelity.Timing)
      assert(timing.name.contains("_timing") && timing.name.replace("_timing", "") == full.name)
      for (prep <- Seq(small, large)) {
        val (fs, fr, _) = resultBeats(prep, full, seed)
        val (ts, tr, verdict) = resultBeats(prep, timing, seed)
        assert(fs.fidelity == "full" && ts.fidelity == "timing")
        assert(verdict.contains("colours from the model"), verdict)
        assert(fr.size == prep.model.count && fr.nonEmpty)
        assert(tr == fr, s"${prep.name}: result beats differ, first at ${fr.zip(tr).indexWhere(x => x._1 != x._2)}")
        assert(ts.cycles == fs.cycles)
        assert(ts.counters.removed("soPassed") == fs.counters.removed("soPassed"))
        assert(fs.counters("soPassed") == prep.model.passing && ts.counters("soPassed") == 0, "the timing model computes no cond")
        assert(ts.soPassingCond == fs.soPassingCond, "the harness's cond count, from the model in timing mode")
        assert(ts.stallCycles == fs.stallCycles && ts.caches == fs.caches)
        assert(ts.bytesFetched == fs.bytesFetched && ts.memoryRequests == fs.memoryRequests)
        info(s"${prep.name}: ${fs.cycles} cycles, ${fr.size} result beats identical")
      }
    }

  test("conventional arithmetic, 2/1/2 fp32: every SO exact under random memory timing; the same TS ops and SOs as online") {
    assume(haveVerilator, "verilator is not on PATH")
    val online = large // writes large.json
    val conv = RtlRun.prepare(dir.resolve("large.json").toString, Some(FloatFormat.fp32), 3, dir.toString, 2, arith = Arith.Conventional)
    // The conventional TSA's decisions are the exact ones, as the online TSA's are: the same search.
    assert(conv.model.tsOps == online.model.tsOps && conv.model.count == online.model.count)
    assert(conv.model.passing == online.model.passing, "the same cond check")
    val p = Configure.of(2, 1, 2, FloatFormat.fp32, 3, arith = Arith.Conventional)
    assert(p.name.contains("_conv"))
    check(conv, p, stress, Seq(22L, 23L))
  }

  // Every slot size: 2-byte (fp16 at g = 2, bf16 packed), 4-byte (fp16 wide; fp32 above) and 8-byte (fp64).
  for ((f, layout, slot, g, (t, s, a), seeds) <- Seq((FloatFormat.fp16, SlotLayout.Packed, 2, 2, (2, 2, 2), Seq(11L, 12L)),
                                                     (FloatFormat.bf16, SlotLayout.Packed, 2, 3, (1, 1, 2), Seq(18L)),
                                                     (FloatFormat.fp16, SlotLayout.Wide, 4, 3, (1, 1, 1), Seq(20L)),
                                                     (FloatFormat.fp64, SlotLayout.Packed, 8, 3, (1, 1, 1), Seq(21L))))
    test(s"${f.name} $layout at $t/$s/$a, g = $g: every SO exact under random memory timing, the frame bit-equal") {
      assume(haveVerilator, "verilator is not on PATH")
      val prep = RtlRun.prepare(scene(s"${f.name}-$layout-g$g", 6, 5, 3, 300, "100").toString, Some(f), g, dir.toString, 2, layout)
      val p = Configure.of(t, s, a, f, g, layout = layout)
      assert(p.slotBytes == slot && prep.model.count > 100)
      assert(MemoryImage.read(prep.image).slot == slot, "the image the harness reads has the hardware's slots")
      check(prep, p, stress, seeds)
    }

  test("Register-queue extreme: h beyond the scene, every node yields two children, a minimal bank; never overflows") {
    assume(haveVerilator, "verilator is not on PATH")
    // h = 10,000 mm covers the whole box: TC_L and TC_R hold at every node, so every non-leaf
    // child is searched and every photon is an SO of every query.
    val prep = RtlRun.prepare(scene("everything", 3, 2, 2, 1000, "10000").toString, Some(FloatFormat.fp32), 3, dir.toString, 2)
    val nonLeaf = (0 until prep.frame.map.size).count(i => prep.frame.map.tree.hasLeft(i) || prep.frame.map.tree.hasRight(i))
    assert(prep.model.tsOps == prep.frame.querySet.size.toLong * nonLeaf, "every non-leaf node is searched for every query")
    assert(prep.model.count == prep.frame.querySet.size.toLong * 1000, "every photon is an SO of every query")
    // The smallest bank the parameters allow: 26 entries, of which K = 10 are the depth reserve.
    val minimal = Configure.of(1, 1, 1, FloatFormat.fp32, 3, tuning = mapm.pipeline.Tuning(registerQueueDepth = Some(26)))
    val stats = check(prep, minimal, stress, Seq(13L)) ++ check(prep, Configure.of(2, 1, 2, FloatFormat.fp32, 3), stress, Seq(14L))
    val peaks = stats.map(_.counters("rqPeak"))
    assert(peaks.head <= 26 && peaks.head >= 16, s"the minimal bank filled up to ${peaks.head} of 26")
    assert(stats.head.counters("stallRqFull") > 0, "the Register-queue rule held work back")
    // Three SOs per TS op from two TSMs against two SOAs: every reservation station fills and the
    // TS block stalls on them.
    assert(stats(1).counters("stallRsFull") > 0)
    info(s"Register-queue peaks ${peaks.mkString(", ")} (banks of 26 and ${Configure.of(2, 1, 2, FloatFormat.fp32, 3).queues.registerQueueDepth}); ${prep.model.tsOps} TS ops, ${prep.model.count} SOs")
  }

  test("edge cases: empty tree, one photon, one query") {
    assume(haveVerilator, "verilator is not on PATH")
    val p = MapmParams.small
    val empty = RtlRun.prepare(scene("empty", 4, 3, 2, 0, "30").toString, Some(FloatFormat.fp32), 3, dir.toString, 2)
    assert(empty.model.count == 0 && empty.model.tsOps == 0)
    val s0 = check(empty, p, stress, Seq(15L)).head
    assert(s0.queries == empty.frame.querySet.size)
    val one = RtlRun.prepare(scene("one-photon", 4, 3, 2, 1, "10000").toString, Some(FloatFormat.fp32), 3, dir.toString, 2)
    assert(one.model.count == one.frame.querySet.size && one.model.tsOps == one.frame.querySet.size)
    check(one, p, stress, Seq(16L))
    // One pixel, one final-gather ray: the first seed whose ray stays in the box (the front is open).
    val single = Iterator.from(1).map(seed =>
      RtlRun.prepare(scene("one-query", 1, 1, 1, 200, "150", seed).toString, Some(FloatFormat.fp32), 3, dir.toString, 2))
      .find(_.frame.querySet.size == 1).get
    assert(single.model.count > 0)
    check(single, p, stress, Seq(17L))
  }
}
