package mapm.evaluation

import mapm.pipeline.{Configure, RunSettings}

import java.nio.charset.StandardCharsets.UTF_8
import java.nio.file.{Files, Path, Paths}

import mapm.MapmError
import mapm.params.Fidelity
import mapm.sim.HarnessStats

/** The results page `evaluate` writes: the dissertation's Tables 4.8-4.11 and 4.13 beside ours,
  * the differences explained with the measured figures, and the charts (PNGs in `results/` next
  * to the page). Every figure of ours comes from the runs' `stats.json` and the unit cost reports;
  * the dissertation's from [[Dissertation]]. */
object ResultsDoc {
  type Rows = Seq[(Workloads.Workload, Seq[SweepReport.Row])]

  private def n(x: Long): String = f"$x%,d"
  private def d(x: Double, digits: Int = 3): String = if (x.isNaN || x.isInfinite) "" else s"%,.${digits}f".format(x)
  private def opt(x: Option[Double], digits: Int = 3): String = x.map(d(_, digits)).getOrElse("—")
  private def label(c: (Int, Int, Int)) = s"${c._1}/${c._2}/${c._3}"

  /** Another full run's figures, shown beside this run's (`evaluate --beside LABEL=PAGE`, e.g. the
    * Table 4.2 hierarchy's run beside the default's): `label` heads its columns, `page` is its
    * results page, `stats` its kept runs ([[RunArchive.keptStats]]) by workload and configuration. */
  final case class Beside(label: String, page: String, stats: Map[(String, (Int, Int, Int)), HarnessStats]) {
    def of(w: String, c: (Int, Int, Int)): Option[HarnessStats] = stats.get((w, c))
  }

  object Beside {
    /** The run of `spec` (`LABEL=PAGE`): the kept runs of `workloads` in PAGE's `results/runs/`. */
    def load(spec: String, workloads: Seq[Workloads.Workload]): Beside = {
      val i = spec.indexOf('=')
      MapmError.check(i > 0 && i < spec.length - 1, s"evaluate: --beside takes LABEL=PAGE (e.g. table4.2=docs/results-table4.2/results.md), got '$spec'")
      val (label, page) = (spec.take(i).trim, spec.drop(i + 1).trim)
      MapmError.check(label.nonEmpty && !label.exists("|`".contains(_)), s"evaluate: --beside: the label '$label' must be non-empty and free of | and `")
      val archive = RunArchive.beside(Paths.get(page))
      MapmError.check(Files.isDirectory(archive.dir), s"evaluate: --beside $spec: no run archive at ${archive.dir}")
      val stats = (for (w <- workloads; c <- w.configs; s <- archive.keptStats(w.key, c)) yield (w.key, c) -> s).toMap
      MapmError.check(stats.nonEmpty, s"evaluate: --beside $spec: ${archive.dir} keeps no run of these workloads and configurations")
      Beside(label, page, stats)
    }
  }

  /** How the runs were made: one local part's wall time, the sum of several parts', or merged. */
  def wall(parts: Seq[RunArchive.Part]): String = {
    def machine(p: RunArchive.Part) = s"--jobs ${p.jobs} on a ${p.cores}-core machine"
    parts match {
      case Seq() => " (merged from their result files by --collect, as a Slurm run does)"
      case Seq(p) => f", ${p.wallSeconds}%.0f s wall with ${machine(p)}"
      case ps => f", ${ps.map(_.wallSeconds).sum}%.0f s wall in ${ps.size} parts run one after another (their sum; " +
        ps.map(p => f"part ${p.index}: ${p.runs} runs in ${p.wallSeconds}%.0f s, started ${p.started}, ${machine(p)}").mkString("; ") + ")"
    }
  }

  /** Writes the page and its charts; returns the files written. `settings` are those the runs
    * shared (the scene aside): the page states their number format (None: the scenes'), guard
    * digits, arithmetic, fidelity, sizes and memory model. */
  def write(file: Path, rows: Rows, cost: SweepReport.Cost, quick: Boolean, settings: RunSettings,
            parts: Seq[RunArchive.Part], beside: Option[Beside] = None): Seq[Path] = {
    val chartDir = Option(file.toAbsolutePath.getParent).getOrElse(file.toAbsolutePath).resolve("results")
    Files.createDirectories(chartDir)
    val charts = rows.map { case (w, rs) => w -> SweepReport.charts(chartDir, w.key, w.title, rs, Some(cost), cost.clockGHz) }
    for ((w, rs) <- rows) Files.write(chartDir.resolve(s"${w.key}-sweep.csv"), SweepReport.csv(rs, Some(cost), cost.clockGHz).getBytes(UTF_8))
    Files.write(file, markdown(rows, cost, quick, settings, parts, file, charts, beside).getBytes(UTF_8))
    file +: charts.flatMap(_._2)
  }

  /** `parts`: the local runs that made the rows, one after another (none: merged by `--collect`);
    * `beside`: another run whose cycles Tables 4.8 and 4.11 show beside these. */
  def markdown(rows: Rows, cost: SweepReport.Cost, quick: Boolean, settings: RunSettings, parts: Seq[RunArchive.Part],
               file: Path, charts: Seq[(Workloads.Workload, Seq[Path])], beside: Option[Beside] = None): String = {
    val page = new Page(rows, cost, settings, beside, file)
    page.header(settings.fidelity, quick, parts)
    page.table410(); page.table48(); page.table49(); page.table411(); page.table413()
    page.differences()
    page.charts(charts)
    page.text
  }

  /** The page as it is written, a section at a time. */
  private final class Page(rows: Rows, cost: SweepReport.Cost, settings: RunSettings, beside: Option[Beside], file: Path) {
    private val sb = new StringBuilder
    private def line(s: String = ""): Unit = sb ++= s + "\n"
    private val byKey = rows.map { case (w, rs) => w.key -> rs.map(r => r.c -> r).toMap }.toMap
    private def stats(w: String, c: (Int, Int, Int)) = byKey.get(w).flatMap(_.get(c)).flatMap(_.stats)
    private val clk = cost.clockGHz
    private val dc = Dissertation.clockGHz
    private val c16 = (16, 16, 2)
    // The 16/16/2 the runs used (format, layout and sizes as given), for record and cache sizes.
    private val p16 = Configure.of(16, 16, 2, settings.format.getOrElse(mapm.numerics.FloatFormat.fp32), settings.g, settings.layout,
      settings.arith, tuning = settings.tuning)
    private val soqLine = p16.caches.soq.lineBytes

    def text: String = sb.toString
    /** The page's folder: the charts and the page beside it are linked relative to it. */
    private val base = Option(file.toAbsolutePath.getParent).getOrElse(file.toAbsolutePath)

    /** The column heads and cells of the run beside ours, for workload `w`, configuration `c`. */
    private def besideHead: String = beside.map(b => s" cycles (${b.label}) | ${b.label} / ours |").getOrElse("")
    private def besideRule: String = if (beside.isEmpty) "" else "---:|---:|"
    private def besideCells(w: String, c: (Int, Int, Int)): String = beside.map { b =>
      val o = b.of(w, c)
      s" ${o.map(x => n(x.cycles)).getOrElse("—")} | ${opt(for (x <- o; s <- stats(w, c)) yield x.cycles.toDouble / s.cycles)} |"
    }.getOrElse("")

    /** The title, how the runs were made and checked, and the settings. */
    def header(fidelity: Fidelity, quick: Boolean, parts: Seq[RunArchive.Part]): Unit = {
      line("# Results: the dissertation's chapter 4, reproduced")
      line()
      line(s"Written by `tools/mapm evaluate${if (quick) " --quick" else ""}` (do not edit by hand; rerun it). " +
        s"${rows.map(_._2.size).sum} RTL runs on ${rows.size} workloads" +
        wall(parts) + ".")
      if (quick) line(s"This is the quick run: the ${Workloads.quickConfigs.map(label).mkString(" and ")} rows of each table alone. `tools/mapm evaluate` runs them all.")
      line()
      line(s"- Every run is checked as `render` checks it: ${if (fidelity == Fidelity.Timing) "in timing fidelity (the SOAs as their cycle-exact delay-line model, proved equal in cycles and counters by MapmRtlSpec): the (q, photon) results, counts and cycles checked, colours taken from the model" else "full RTL: every shader operation's colour bit-exact against the model, the frame bit-equal"}.")
      line(s"- Number format ${settings.format.map(_.toString).getOrElse("fp32")}, g = ${settings.g}, ${settings.arith} arithmetic; ${settings.tuning.summary}; the queries streamed in ${settings.queryOrder} order; memory latency ${settings.harness.latency} cycles, ${settings.harness.bandwidth} bytes/cycle.")
      line(f"- Cost by the dissertation's method (Table 4.9: unit figures times counts), from our open flow (yosys, OpenSTA, OSU 0.18 um): ${cost.soa.top} ${cost.soa.areaUm2 / 1e6}%.4f mm^2, fmax ${cost.soa.fmaxGHz * 1000}%.0f MHz, ${cost.soa.dynamicPjPerCycle}%.0f pJ/cycle; ${cost.tsa.top} ${cost.tsa.areaUm2 / 1e6}%.4f mm^2, fmax ${cost.tsa.fmaxGHz * 1000}%.0f MHz, ${cost.tsa.dynamicPjPerCycle}%.0f pJ/cycle (docs/cost.md).")
      for (b <- beside) line(s"- Beside ours, the run of [${b.page}](${base.relativize(Paths.get(b.page).toAbsolutePath)}) (**${b.label}**, its ${b.stats.size} runs kept in its results/runs/, " +
        s"made with other code or options): its cycles in the columns \"cycles (${b.label})\", and its cycles over ours in \"${b.label} / ours\" (above 1: ours take fewer cycles).")
      line(f"- Throughput, power and GB/s of ours at **$clk%.3f GHz** (${cost.clockSource}) where a column says \"at fmax\"; at the dissertation's 1.5 GHz where it says so, to compare cycles alone. The dissertation's figures are at 90 nm and 1.5 GHz.")
      line()
    }

    /** Table 4.10: operation counts per workload. */
    def table410(): Unit = {
      line("## Table 4.10: operation counts")
      line()
      line("| workload | queries (diss.) | queries (ours) | TS ops (diss.) | TS ops (ours) | SOs (diss.) | SOs (ours) |")
      line("|---|---:|---:|---:|---:|---:|---:|")
      for ((w, rs) <- rows) {
        val diss = if (w.key == "cornell-2k") Some(Dissertation.cornell2kOps) else Dissertation.table410.get(w.key)
        val s = rs.flatMap(_.stats).headOption
        line(s"| ${w.title} | ${diss.map(x => n(x._1)).getOrElse("")} | ${s.map(x => n(x.queries)).getOrElse("—")} | ${diss.map(x => n(x._2)).getOrElse("")} | " +
          s"${s.flatMap(_.tsOps).map(n).getOrElse("—")} | ${diss.map(x => n(x._3)).getOrElse("")} | ${s.map(x => n(x.soIssued)).getOrElse("—")} |")
      }
      line()
      line("The Cornell 2k row's dissertation figures are from the text of section 4.3.2 (Table 4.8's workload). Our scenes are ours: the " +
        "Cornell box as measured, the Sponza views chosen by us (docs/evaluation.md), so the counts differ in detail; they are of the same order.")
      line()
    }

    /** Table 4.8: cycles and throughput, Cornell box 2k. */
    def table48(): Unit = {
      line("## Table 4.8: cycles and throughput, Cornell box 2k")
      line()
      line("| TSMs/SOMs/SOAs | cycles (diss.) | cycles (ours) | ours / diss. | BSO/s (diss., 1.5 GHz) | BSO/s (ours, 1.5 GHz) | BSO/s (ours, at fmax) |" + besideHead)
      line("|---|---:|---:|---:|---:|---:|---:|" + besideRule)
      for ((c, cyc, bso) <- Dissertation.table48 if byKey("cornell-2k").contains(c)) {
        val s = stats("cornell-2k", c)
        line(s"| ${label(c)} | ${n(cyc)} | ${s.map(x => n(x.cycles)).getOrElse("—")} | ${opt(s.map(_.cycles.toDouble / cyc))} | ${d(bso)} | " +
          s"${opt(s.map(_.soPerCycle * dc))} | ${opt(s.map(_.soPerCycle * clk))} |" + besideCells("cornell-2k", c))
      }
      line()
    }

    /** Table 4.9: performance per hardware cost, Cornell box 2k. */
    def table49(): Unit = {
      line("## Table 4.9: performance per hardware cost, Cornell box 2k")
      line()
      line("| TSMs/SOMs/SOAs | BSO/s (diss.) | area mm^2 (diss.) | MSO/s/mm^2 (diss.) | power mW (diss.) | BSO/s/W (diss.) | BSO/s (ours, fmax) | area mm^2 (ours) | MSO/s/mm^2 (ours) | power mW (ours) | BSO/s/W (ours) |")
      line("|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|")
      for ((c, _, bso) <- Dissertation.table48 if byKey("cornell-2k").contains(c)) {
        val (a, pa, p, pp) = Dissertation.table49(c)
        val f = SweepReport.figures(byKey("cornell-2k")(c), Some(cost), clk)
        line(s"| ${label(c)} | ${d(bso)} | ${d(a)} | ${d(pa)} | ${d(p, 2)} | ${d(pp)} | ${opt(f.bsoPerS)} | ${opt(f.areaMm2)} | ${opt(f.perArea)} | ${opt(f.powerMw, 1)} | ${opt(f.perPower)} |")
      }
      line()
    }

    /** Table 4.11: cycles and throughput of the 8k-photon workloads. */
    def table411(): Unit = {
      line("## Table 4.11: cycles and throughput, 8k-photon workloads")
      line()
      for ((w, rs) <- rows if w.key != "cornell-2k") {
        line(s"### ${w.title}")
        line()
        line("| setup | cycles (diss.) | cycles (ours) | ours / diss. | TP (diss., 1.5 GHz) | TP (ours, 1.5 GHz) | TP (ours, at fmax) |" + besideHead)
        line("|---|---:|---:|---:|---:|---:|---:|" + besideRule)
        for (((c, (cyc, tp)), i) <- Dissertation.table411Configs.zip(Dissertation.table411(w.key)).zipWithIndex if rs.exists(_.c == c)) {
          val s = stats(w.key, c)
          line(s"| ${label(c)} | ${n(cyc)} | ${s.map(x => n(x.cycles)).getOrElse("—")} | ${opt(s.map(_.cycles.toDouble / cyc))} | ${d(tp)}${if (w.key == "cornell-8k" && i == 1) " (sic)" else ""} | " +
            s"${opt(s.map(_.soPerCycle * dc))} | ${opt(s.map(_.soPerCycle * clk))} |" + besideCells(w.key, c))
        }
        line()
      }
      if (byKey.get("cornell-8k").exists(_.contains((1, 1, 3)))) {
        line("(sic): the dissertation prints 1.118 for Cornell 8k at 1/1/3; its own cycles give 26,478,415 / 18,754,570 x 1.5 = 2.118.")
        line()
      }
    }

    /** Table 4.13: memory traffic and bandwidth at 16/16/2. */
    def table413(): Unit = {
      line("## Table 4.13: memory traffic and bandwidth, 16/16/2")
      line()
      line("| workload | cycles (diss.) | memory B (diss.) | GB/s (diss., 1.5 GHz) | cycles (ours) | memory B (ours) | GB/s (ours, 1.5 GHz) | GB/s (ours, at fmax) | SOQ share of bytes (ours) |")
      line("|---|---:|---:|---:|---:|---:|---:|---:|---:|")
      var tot = (0L, 0L)
      for ((k, cyc, bytes, gbs) <- Dissertation.table413) {
        val s = stats(k, c16)
        s.foreach(x => tot = (tot._1 + x.cycles, tot._2 + x.bytesFetched))
        val soqShare = s.flatMap(x => x.caches.get("soq").filter(_ => x.bytesFetched > 0).map(q => q.misses.toDouble * soqLine / x.bytesFetched))
        line(s"| ${rows.find(_._1.key == k).map(_._1.title).getOrElse(k)} | ${n(cyc)} | ${n(bytes)} | ${d(gbs)} | ${s.map(x => n(x.cycles)).getOrElse("—")} | " +
          s"${s.map(x => n(x.bytesFetched)).getOrElse("—")} | ${opt(s.map(x => x.bytesFetched.toDouble / x.cycles * dc))} | " +
          s"${opt(s.map(x => x.bytesFetched.toDouble / x.cycles * clk))} | ${soqShare.map(x => f"${x * 100}%.0f %%").getOrElse("—")} |")
      }
      val (tc, tb, tg) = Dissertation.table413Total
      line(s"| Total | ${n(tc)} | ${n(tb)} | ${d(tg)} | ${if (tot._1 > 0) n(tot._1) else "—"} | ${if (tot._1 > 0) n(tot._2) else "—"} | " +
        s"${if (tot._1 > 0) d(tot._2.toDouble / tot._1 * dc) else "—"} | ${if (tot._1 > 0) d(tot._2.toDouble / tot._1 * clk) else "—"} | |")
      line()
    }

    /** Where ours differ from the dissertation's, and why, from the measured figures. */
    def differences(): Unit = {
      line("## Where ours differ, and why")
      line()
      val ts2k = stats("cornell-2k", c16)
      val (_, dissTs, _) = Dissertation.cornell2kOps
      val dissCyc = Dissertation.table48.find(_._1 == c16).map(_._2).getOrElse(1L)
      line(f"- **TS ops per cycle.** The dissertation's Cornell 2k workload counts ${n(dissTs)} tree-search operations, done in ${n(dissCyc)} cycles " +
        f"at 16/16/2: ${dissTs.toDouble / dissCyc}%.1f TS ops per cycle from 16 TSMs, each of which issues at most one per cycle. Its TS-op count cannot " +
        s"be the one its cycle model executed. Ours counts every node visit the TSAs perform${ts2k.flatMap(t => t.tsOps.map(o => f": ${n(o)} in ${n(t.cycles)} cycles, ${o.toDouble / t.cycles}%.2f per cycle (at most 16)")).getOrElse("")}.")
      val shares = rows.flatMap { case (w, _) => stats(w.key, c16) }.filter(_.bytesFetched > 0)
        .flatMap(x => x.caches.get("soq").map(q => q.misses.toDouble * soqLine / x.bytesFetched))
      val soq2k = ts2k.flatMap(x => x.caches.get("soq").map(q => (q.misses, x.queries)))
      val soqWays = if (p16.caches.soq.ways == 1) "direct-mapped" else s"${p16.caches.soq.ways}-way"
      line(s"- **Bandwidth.** Our query records stream through the SOQ, a $soqWays ${p16.caches.soq.sizeBytes / 1024} KiB cache: " +
        soq2k.map { case (m, q) => s"at Cornell 2k it missed ${n(m)} times for ${n(q)} queries, so each query's record is read from memory " +
          (if (m == q) "exactly once" else f"${m.toDouble / q}%.2f times on average") + ", " }.getOrElse("") +
        (if (shares.isEmpty) "" else f"and those reads are ${shares.min * 100}%.0f %% to ${shares.max * 100}%.0f %% of the bytes fetched at 16/16/2 (the last column of Table 4.13). ") +
        f"The dissertation counts every cache's misses times its block size in a Pin-based simulation (section 4.3.3); its Cornell 2k total is " +
        f"${Dissertation.table413.head._3.toDouble / Dissertation.cornell2kOps._1}%.1f bytes per query, less than one ${soqLine}-byte line per query, " +
        "so its query records cannot have streamed as ours do. Ours are the bytes the RTL fetched.")
      // The shared photon L2 takes one request per cycle: where the photon set outgrows the SOP L1 banks, it bounds the SO rate.
      val photonBytes = p16.records.photon.bytes
      val l1Bank = p16.sopL1Bank.sizeBytes
      val l2 = for ((w, _) <- rows; x <- stats(w.key, c16); l1 <- x.caches.get("sopL1"); l2 <- x.caches.get("sopL2"))
        yield (w, x, l1.hitRate, (l2.hits + l2.misses).toDouble / x.cycles)
      val banks = p16.uncore.sopL2.banks
      if (l2.nonEmpty) {
        line((if (banks == 1) s"- **The shared SOP L2's port.** Every SOP L1 miss goes to the one SOP L2, which takes one request per cycle (docs/memory-port.md). "
          else s"- **The SOP L2's ports.** Every SOP L1 miss goes to its line's bank of the SOP L2, $banks banks that each take one request per cycle (docs/uncore.md). ") +
          s"At 16/16/2: " + l2.map { case (w, x, h1, a2) =>
            f"${w.title}: SOP L1 hit rate ${h1 * 100}%.1f %%, ${a2}%.3f SOP L2 requests per cycle, ${x.soPerCycle}%.2f SO/cycle" }.mkString("; ") + ". " +
          f"A photon record is $photonBytes bytes and each SOA's ${l1Bank / 1024} KiB SOP L1 bank holds every second photon: 2,000 photons put " +
          f"${1000L * photonBytes / 1024.0}%.1f KiB in each bank, which fits, and 8,000 put ${4000L * photonBytes / 1024.0}%.0f KiB, which does not. " +
          (if (l2.exists(_._4 > 0.5 * banks)) "Where the L2's ports run at more than half a request per cycle each, they bound the SO rate, and more SOMs add " +
            "misses, not throughput. The dissertation's 8k figures keep scaling to 16/16/2; its cache model (section 4.1.3) sizes the caches but " +
            "does not describe a port limit. "
          else "In these runs the L2's ports stay below half a request per cycle each and are not the bound. ") +
          "`--sop-l1` and `--sop-l2` on `sweep` and `render` vary the caches.")
      }
      for (b <- beside) {
        val at16 = for ((w, _) <- rows; x <- stats(w.key, c16); y <- b.of(w.key, c16)) yield (w, x, y)
        if (at16.nonEmpty) line(s"- **The memory hierarchy.** Ours against ${b.label} at 16/16/2, SO/cycle: " + at16.map { case (w, x, y) =>
          f"${w.title}: ${x.soPerCycle}%.2f against ${y.soPerCycle}%.2f (${y.cycles.toDouble / x.cycles}%.2fx)" }.mkString("; ") +
          ". docs/uncore.md measures each part of the hierarchy on its own.")
      }
      line(f"- **Node and clock.** Our cells are OSU's 0.18 um library (typical corner, 1.8 V), not the dissertation's 90 nm; our units close at " +
        f"${cost.soa.fmaxGHz * 1000}%.0f MHz (SOA) and ${cost.tsa.fmaxGHz * 1000}%.0f MHz (TSA), not 1.5 GHz. Area and power per unit are therefore " +
        "far larger and throughput per area and per power far lower; the ratios between configurations are what carries over.")
      line("- **Scenes.** The Sponza cameras and lights are ours (the dissertation's Figures 4.3 and 4.4 are lost); the Cornell box is the measured one with the " +
        "point light of section 3.1.2. Query and operation counts differ from Table 4.10 accordingly.")
      line()
    }

    /** The charts, linked relative to the page. */
    def charts(charts: Seq[(Workloads.Workload, Seq[Path])]): Unit = {
      line("## Charts (Figures 4.9-4.20)")
      line()
      for ((w, fs) <- charts) {
        line(s"### ${w.title}")
        line()
        for (f <- fs) line(s"![${f.getFileName}](${base.relativize(f.toAbsolutePath)})")
        line()
      }
    }
  }
}
