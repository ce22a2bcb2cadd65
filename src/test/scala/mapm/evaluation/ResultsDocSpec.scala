package mapm.evaluation

import mapm.costflow._

import java.nio.file.{Files, Paths}

import mapm.sim.HarnessStats
import org.scalatest.funsuite.AnyFunSuite

/** The results page from given runs: every table of chapter 4 present, the dissertation's figures
  * beside ours, ours derived from the runs' stats as the columns say (checked here by hand
  * arithmetic on the inputs), and the charts on disk and linked. */
class ResultsDocSpec extends AnyFunSuite {
  /** A stats.json of `cycles` cycles, `so` SOs, `ts` TS ops, `bytes` fetched, `soqMisses` SOQ misses. */
  private def stats(cycles: Long, so: Long, ts: Long, bytes: Long, soqMisses: Long): HarnessStats =
    HarnessStats.parse(ujson.write(mapm.testutil.StatsFixture.json(cycles, so, ts, bytes, soqMisses)), "test")

  test("evaluate's page: Tables 4.10, 4.8, 4.9, 4.11 and 4.13 side by side, ours from the runs, charts written and linked") {
    val dir = Paths.get("target/results-doc-test")
    mapm.sim.AtomicDir.delete(dir)
    val ws = Workloads.of(quick = true)
    assert(ws.map(_.configs) == Seq.fill(4)(Seq((4, 4, 2), (16, 16, 2))))
    // ours: half the dissertation's cycles (2k: Table 4.8's; 8k: Table 4.11's), 12 SO per cycle, 3 TS ops per cycle, 2 bytes per cycle
    def cyclesOf(key: String, c: (Int, Int, Int)): Long =
      if (key == "cornell-2k") Dissertation.table48.find(_._1 == c).get._2 / 2
      else Dissertation.table411(key)(Dissertation.table411Configs.indexOf(c))._1 / 2
    val rows = ws.map(w => w -> w.configs.map { c =>
      val cy = cyclesOf(w.key, c)
      SweepReport.Row(c, SweepReport.TaskResult(s"${c._1}/${c._2}/${c._3}", c._1, c._2, c._3, passed = true, "", Seq.empty),
        Some(stats(cy, 12 * cy, 3 * cy, 2 * cy, cy / 64)))
    })
    val unit = (u: String, area: Double, fmax: Double, pj: Double) =>
      UnitCostCache.Figures(u, u.toUpperCase + "_x", fmax, area, pj, 0.5, "test", dir.resolve(s"$u.json"))
    val cost = SweepReport.Cost(unit("soa", 6e6, 0.3, 300), unit("tsa", 0.25e6, 0.6, 2), 0.3, "fmax of the slower unit, the SOA")
    val file = dir.resolve("results.md")
    val files = ResultsDoc.write(file, rows, cost, quick = true,
      mapm.pipeline.RunSettings("test-scenes/cornell-box/scene.json", None, mapm.format.SlotLayout.Packed, 3, mapm.numerics.Arith.Online,
        mapm.params.Fidelity.Timing, mapm.sim.Harness.RunOptions(latency = 100, bandwidth = 14.0), "out", 1, mapm.pipeline.Tuning()), Seq(RunArchive.Part(1, "2026-12-04T10:00Z", 123.0, 2, 2, 8)))
    val md = new String(Files.readAllBytes(file), "UTF-8")
    for (t <- Seq("Table 4.10", "Table 4.8", "Table 4.9", "Table 4.11", "Table 4.13")) assert(md.contains(s"## $t"), t)
    // The settings the runs shared, as the page states them (timing fidelity, the memory hierarchy, the memory model).
    assert(md.contains("- Number format fp32, g = 3, online arithmetic; the scalable memory hierarchy (docs/uncore.md), Table 4.2's capacities; the queries streamed in morton order; memory latency 100 cycles, 14.0 bytes/cycle."), md)
    assert(md.contains("in timing fidelity (the SOAs as their cycle-exact delay-line model"), md)
    for (w <- ws.tail) assert(md.contains(s"### ${w.title}"))
    // Table 4.8, 16/16/2: the dissertation's cycles and BSO/s, ours half the cycles, 12 SO/cycle = 18 BSO/s at 1.5 GHz, 3.6 at 0.3 GHz
    assert(md.contains("| 16/16/2 | 476,341 | 238,170 | 0.500 | 26.012 | 18.000 | 3.600 |"), md)
    // Table 4.9, 16/16/2: 32 SOAs x 6 mm^2 + 16 TSAs x 0.25 mm^2 = 196 mm^2; 3.6 BSO/s / 196 mm^2 = 18.367 MSO/s/mm^2;
    // power 32 x (300 pJ x 0.3 GHz + 0.5) + 16 x (2 x 0.3 + 0.5) = 2,913.6 mW; 3.6 / 2.9136 = 1.236 BSO/s/W
    assert(md.contains("| 16/16/2 | 26.012 | 19.619 | 1,325.813 | 976.64 | 26.634 | 3.600 | 196.000 | 18.367 | 2,913.6 | 1.236 |"), md)
    // Table 4.11, Cornell 8k 4/4/2: half of 4,990,699 cycles
    assert(md.contains("| 4/4/2 | 4,990,699 | 2,495,349 | 0.500 | 7.958 | 18.000 | 3.600 |"))
    // Table 4.13: 2 bytes per cycle = 3 GB/s at 1.5 GHz, 0.6 at 0.3; the SOQ's misses x 32-byte lines over the bytes = 25 %
    assert(md.contains("| Cornell box, 2k photons | 476,341 | 1,534,784 | 4.501 | 238,170 | 476,340 | 3.000 | 0.600 | 25 % |"), md)
    val total = ws.map(w => cyclesOf(w.key, (16, 16, 2))).sum
    assert(md.contains(f"| Total | 4,658,734 | 10,554,304 | 3.165 | $total%,d | ${2 * total}%,d | 3.000 | 0.600 | |"))
    // the dissertation's implied TS-op rate, and ours
    assert(md.contains("109,881,410 tree-search operations, done in 476,341 cycles at 16/16/2: 230.7 TS ops per cycle from 16 TSMs"))
    assert(md.contains(": 714,510 in 238,170 cycles, 3.00 per cycle (at most 16)"))
    assert(md.contains("123 s wall with --jobs 2"))
    // SOQ misses = cycles / 64 for 1,000 queries; their bytes are 25 % of all; the dissertation's 1,534,784 B over 85,105 queries
    assert(md.contains("at Cornell 2k it missed 3,721 times for 1,000 queries, so each query's record is read from memory 3.72 times on average, " +
      "and those reads are 25 % to 25 % of the bytes fetched at 16/16/2"), md)
    assert(md.contains("its Cornell 2k total is 18.0 bytes per query, less than one 32-byte line per query"))
    assert(!md.contains("(sic)"), "the quick run has no 1/1/3 row")
    // 1,000 SOP L2 requests (900 hits, 100 misses) in 238,170 cycles: the ports are not the bound, and the page says so,
    // naming the structure the settings build (the scalable hierarchy: 16 banks at 16/16/2) and the SOQ's 4 ways
    assert(md.contains("Cornell box, 2k photons: SOP L1 hit rate 90.0 %, 0.004 SOP L2 requests per cycle") && md.contains("the L2's ports stay below half a request per cycle each and are not the bound"))
    assert(md.contains("Every SOP L1 miss goes to its line's bank of the SOP L2, 16 banks that each take one request per cycle") && md.contains("through the SOQ, a 4-way 16 KiB cache"), md)
    // charts: four per workload, on disk and linked relative to the page; one CSV per workload
    val pngs = files.filter(_.toString.endsWith(".png"))
    assert(pngs.size == 16 && pngs.forall(f => Files.size(f) > 0))
    for (f <- pngs) assert(md.contains(s"](results/${f.getFileName})"))
    for (w <- ws) assert(Files.isRegularFile(dir.resolve(s"results/${w.key}-sweep.csv")))
  }

  test("--beside: another run's kept cycles stand beside ours in Tables 4.8 and 4.11, its ratio to ours, and the 16/16/2 SO/cycle of both") {
    val dir = Paths.get("target/results-doc-beside")
    mapm.sim.AtomicDir.delete(dir)
    val ws = Workloads.of(quick = true)
    // the other run: kept as evaluate keeps it, beside its page, with 3x ours' cycles at 16/16/2 and 2x at 4/4/2 (no 4/4/2 for the atrium)
    val other = dir.resolve("other/results.md")
    val archive = RunArchive.beside(other)
    for (w <- ws; c <- w.configs if !(w.key == "sponza-atrium" && c == (4, 4, 2))) {
      val run = dir.resolve(s"ran/${w.key}-${c._1}")
      Files.createDirectories(run)
      SweepReport.writeResult(run, SweepReport.TaskResult("x", c._1, c._2, c._3, passed = true, "", Seq.empty))
      val cy = (if (c == (16, 16, 2)) 3000L else 2000L) * (ws.indexOf(w) + 1)
      Files.write(run.resolve("stats.json"), ujson.write(mapm.testutil.StatsFixture.json(cy, 12 * cy / 3, cy, cy, 10)).getBytes("UTF-8"))
      archive.save(w.key, c, "another key", 1, run)
    }
    val b = ResultsDoc.Beside.load(s"table4.2=$other", ws)
    assert(b.label == "table4.2" && b.stats.size == 7)
    // ours: 1,000 x (workload's index + 1) cycles, 12 SO/cycle
    val rows = ws.map(w => w -> w.configs.map { c =>
      val cy = 1000L * (ws.indexOf(w) + 1)
      SweepReport.Row(c, SweepReport.TaskResult(s"${c._1}/${c._2}/${c._3}", c._1, c._2, c._3, passed = true, "", Seq.empty),
        Some(stats(cy, 12 * cy, 3 * cy, 2 * cy, 1)))
    })
    val unit = (u: String) => UnitCostCache.Figures(u, u.toUpperCase + "_x", 0.3, 1e6, 1, 0.5, "test", dir.resolve(s"$u.json"))
    val cost = SweepReport.Cost(unit("soa"), unit("tsa"), 0.3, "fmax")
    val md = ResultsDoc.markdown(rows, cost, quick = true, mapm.pipeline.RunSettings("test-scenes/cornell-box/scene.json", None,
      mapm.format.SlotLayout.Packed, 3, mapm.numerics.Arith.Online, mapm.params.Fidelity.Timing, mapm.sim.Harness.RunOptions(),
      "out", 1, mapm.pipeline.Tuning()), Seq.empty, dir.resolve("results.md"), Seq.empty, Some(b))
    assert(md.contains(s"the run of [$other](other/results.md) (**table4.2**, its 7 runs kept"), md) // linked relative to the page
    assert(md.contains("| BSO/s (ours, at fmax) | cycles (table4.2) | table4.2 / ours |") && md.contains("| TP (ours, at fmax) | cycles (table4.2) | table4.2 / ours |"))
    // Table 4.8 (Cornell 2k, the first workload): 1,000 cycles of ours, 3,000 and 2,000 of the other's
    assert(md.contains("| 16/16/2 | 476,341 | 1,000 | 0.002 | 26.012 | 18.000 | 3.600 | 3,000 | 3.000 |"), md)
    assert(md.contains("| 4/4/2 | 1,760,068 | 1,000 | 0.001 | 7.040 | 18.000 | 3.600 | 2,000 | 2.000 |"), md)
    // Table 4.11, the atrium (the fourth workload): 4,000 cycles of ours; its 4/4/2 is not kept beside
    assert(md.contains("| 4/4/2 | 5,014,895 | 4,000 | 0.001 | 6.594 | 18.000 | 3.600 | — | — |"), md)
    assert(md.contains("| 16/16/2 | 1,338,924 | 4,000 | 0.003 | 24.698 | 18.000 | 3.600 | 12,000 | 3.000 |"), md)
    // the 16/16/2 SO/cycle of both: ours 12, the other's 4 (12 x cy / 3 SOs in cy cycles)
    assert(md.contains("- **The memory hierarchy.** Ours against table4.2 at 16/16/2, SO/cycle: Cornell box, 2k photons: 12.00 against 4.00 (3.00x)"), md)
    // a wrong --beside is a one-line error before any run
    def err(spec: String) = intercept[mapm.MapmError](ResultsDoc.Beside.load(spec, ws)).getMessage
    assert(err("docs/results.md").contains("--beside takes LABEL=PAGE"))
    assert(err("a|b=x.md").contains("the label 'a|b' must be non-empty and free of | and `"))
    assert(err(s"t=${dir.resolve("none/results.md")}").contains("no run archive at"))
  }
}
