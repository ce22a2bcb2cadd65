package mapm.evaluation

import mapm.costflow._

import java.nio.charset.StandardCharsets.UTF_8
import java.nio.file.{Files, Path}

import mapm.MapmError
import mapm.sim.HarnessStats

/** The rows of a sweep and the files made of them: one `result.json` per configuration (written
  * by whichever process ran it: the sweep itself, a local job or a Slurm array task), the CSV and
  * the charts (written by the sweep, or by the Slurm collect step, from those files alone).
  *
  * Cost columns follow the dissertation's method (Table 4.9): the SOA's and TSA's unit figures
  * ([[UnitCostCache]]) times their counts, at the sweep's clock. */
object SweepReport {
  /** What a configuration's run left: its label and counts, the verdict and why, seconds per stage. */
  final case class TaskResult(label: String, tsm: Int, som: Int, soa: Int, passed: Boolean, failure: String,
                              times: Seq[(String, Double)]) {
    def json: ujson.Obj = ujson.Obj("config" -> label, "tsm" -> tsm, "som" -> som, "soa" -> soa, "passed" -> passed,
      "failure" -> failure, "seconds" -> ujson.Obj.from(times.map { case (k, v) => k -> ujson.Num(v) }))
  }

  /** The folder of configuration (t, s, a) under a sweep's work folder. */
  def configDir(work: Path, c: (Int, Int, Int)): Path = work.resolve(s"sweep-${c._1}-${c._2}-${c._3}")

  def writeResult(dir: Path, r: TaskResult): Unit = {
    Files.createDirectories(dir)
    val tmp = dir.resolve("result.json.tmp")
    Files.write(tmp, ujson.write(r.json, indent = 2).getBytes(UTF_8))
    Files.move(tmp, dir.resolve("result.json"), java.nio.file.StandardCopyOption.REPLACE_EXISTING, java.nio.file.StandardCopyOption.ATOMIC_MOVE)
  }

  /** A configuration's row: its result and the harness's stats, or a failed row saying what is missing. */
  final case class Row(c: (Int, Int, Int), result: TaskResult, stats: Option[HarnessStats]) {
    def label: String = result.label
    def passed: Boolean = result.passed && stats.isDefined
  }

  def readRow(work: Path, c: (Int, Int, Int)): Row = {
    val dir = configDir(work, c)
    val label = s"${c._1}/${c._2}/${c._3}"
    val file = dir.resolve("result.json")
    if (!Files.isRegularFile(file)) return Row(c, TaskResult(label, c._1, c._2, c._3, passed = false,
      s"no result in $dir (its job did not finish)", Seq.empty), None)
    val j = try ujson.read(Files.readAllBytes(file)) catch { case e: Exception => MapmError.fail(s"$file: unreadable (${e.getMessage})") }
    val r = TaskResult(j("config").str, j("tsm").num.toInt, j("som").num.toInt, j("soa").num.toInt, j("passed").bool,
      j("failure").str, j("seconds").obj.toSeq.map { case (k, v) => k -> v.num })
    MapmError.check(r.label == label, s"$file: the result of ${r.label}, expected $label")
    val stats = Some(dir.resolve("stats.json")).filter(Files.isRegularFile(_)).map(HarnessStats.read)
    Row(c, r, stats)
  }

  /** The unit figures and the clock the cost columns use. */
  final case class Cost(soa: UnitCostCache.Figures, tsa: UnitCostCache.Figures, clockGHz: Double, clockSource: String) {
    def areaMm2(c: (Int, Int, Int)): Double = (c._2 * c._3 * soa.areaUm2 + c._1 * tsa.areaUm2) / 1e6
    /** Dynamic power at the clock (each unit at its measured activity) plus leakage, mW. */
    def powerMw(c: (Int, Int, Int)): Double = {
      val (nSoa, nTsa) = (c._2 * c._3, c._1)
      nSoa * (soa.dynamicMwAt(clockGHz) + soa.leakageMw) + nTsa * (tsa.dynamicMwAt(clockGHz) + tsa.leakageMw)
    }
  }

  val caches: Seq[String] = Seq("tsL1", "tsL2", "soq", "sopL1", "sopL2")

  val header: Seq[String] = Seq("config", "tsm", "som", "soa", "cycles", "so_per_cycle", "ts_ops_per_cycle", "speedup", "clock_ghz",
    "bso_per_s", "area_mm2", "power_mw", "mso_per_s_per_mm2", "bso_per_s_per_w", "bytes_fetched", "gb_per_s") ++
    caches.map(c => s"hit_rate_$c") ++ Seq("sim_wall_s", "sim_cycles_per_s", "fidelity", "result")

  private def cell(v: Option[Double]): String = v.filter(x => !x.isNaN && !x.isInfinite).map(x => f"$x%.6g").getOrElse("")

  /** The figures of one row at the cost's clock (None without stats, or without cost for the cost columns). */
  final case class Figures(cycles: Option[Long], soPerCycle: Option[Double], bsoPerS: Option[Double], areaMm2: Option[Double],
                           powerMw: Option[Double], gbPerS: Option[Double]) {
    def perArea: Option[Double] = for (b <- bsoPerS; a <- areaMm2 if a > 0) yield b * 1000 / a
    def perPower: Option[Double] = for (b <- bsoPerS; p <- powerMw if p > 0) yield b / (p / 1000)
  }

  def figures(r: Row, cost: Option[Cost], clockGHz: Double): Figures = {
    val s = r.stats
    Figures(s.map(_.cycles), s.map(_.soPerCycle), s.map(_.soPerCycle * clockGHz), cost.map(_.areaMm2(r.c)), cost.map(_.powerMw(r.c)),
      s.filter(_.cycles > 0).map(x => x.bytesFetched.toDouble / x.cycles * clockGHz))
  }

  /** The CSV text: a header and one line per row; speed-up against the first row. */
  def csv(rows: Seq[Row], cost: Option[Cost], clockGHz: Double): String = {
    val base = rows.headOption.flatMap(_.stats).map(_.cycles)
    val lines = rows.map { r =>
      val f = figures(r, cost, clockGHz)
      val s = r.stats
      (Seq(r.label, r.c._1.toString, r.c._2.toString, r.c._3.toString, f.cycles.map(_.toString).getOrElse(""), cell(f.soPerCycle),
        cell(s.flatMap(_.tsOpsPerCycle)), cell(for (b <- base; c <- f.cycles if c > 0) yield b.toDouble / c), cell(Some(clockGHz)),
        cell(f.bsoPerS), cell(f.areaMm2), cell(f.powerMw), cell(f.perArea), cell(f.perPower), s.map(_.bytesFetched.toString).getOrElse(""),
        cell(f.gbPerS)) ++
        caches.map(c => cell(s.flatMap(_.caches.get(c)).map(_.hitRate))) ++
        Seq(cell(s.map(_.wallSeconds)), cell(s.map(_.simulatedCyclesPerSecond)), s.map(_.fidelity).getOrElse(""),
          if (r.passed) "PASS" else "FAIL")).mkString(",")
    }
    (header.mkString(",") +: lines).mkString("", "\n", "\n")
  }

  /** The charts of Figures 4.9-4.20 for these rows, grouped by TSM count: SO/cycle, throughput
    * and (with cost) throughput per area and per power. Returns the files written. */
  def charts(dir: Path, name: String, what: String, rows: Seq[Row], cost: Option[Cost], clockGHz: Double): Seq[Path] = {
    def nan(v: Option[Double]) = v.getOrElse(Double.NaN)
    val fs = rows.map(r => r.label -> figures(r, cost, clockGHz))
    val group: String => String = l => s"${l.takeWhile(_ != '/')} TSM"
    val clock = f"$clockGHz%.3g GHz"
    val specs = Seq(
      ("so-per-cycle", s"Shader operations per cycle ($what)", "SO / cycle", (f: Figures) => f.soPerCycle),
      ("throughput", s"Throughput ($what, $clock)", "billion SO / s", (f: Figures) => f.bsoPerS)) ++
      (if (cost.isEmpty) Seq.empty else Seq(
        ("per-area", s"Throughput per area ($what, $clock)", "million SO / s / mm^2", (f: Figures) => f.perArea),
        ("per-power", s"Throughput per power ($what, $clock)", "billion SO / s / W", (f: Figures) => f.perPower)))
    specs.map { case (file, title, y, pick) =>
      val path = dir.resolve(s"$name-sweep-$file.png")
      BarChart.write(path, title, y, fs.map { case (l, f) => l -> nan(pick(f)) }, group)
      path
    }
  }
}
