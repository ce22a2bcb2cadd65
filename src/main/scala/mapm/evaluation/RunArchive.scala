package mapm.evaluation

import java.nio.charset.StandardCharsets.UTF_8
import java.nio.file.{Files, Path, StandardCopyOption}

import scala.jdk.CollectionConverters._

import mapm.MapmError
import mapm.sim.{Harness, HarnessStats, Verilator}

/** The finished runs of a full `evaluate`, kept in the repository beside its results page
  * (`<page's folder>/results/runs/`), so that the evaluation can be run in parts, in one session
  * or over several machines one after the other (`evaluate --budget MIN`, then `--resume`).
  *
  * One file per run, `runs/<workload>/<t>-<s>-<a>.json`: the run's [[key]], the part that ran it,
  * its `result.json` and its harness `stats.json`. A record is taken again only when its key is
  * the key of the run asked for: the key hashes everything that decides a run's figures (the
  * hardware, model, format and harness sources, the scene file and every run option), so a record
  * of other code or other options is run again, never mixed in. Only passed runs are kept.
  *
  * `runs/parts.json` lists the parts (start, wall seconds, jobs, cores, runs finished): the full
  * evaluation's wall time is their sum (each part counts the builds it needed; a job that was
  * still running when a part was killed is not counted, nor kept). */
final class RunArchive(val dir: Path) {
  import RunArchive._

  private def file(workload: String, c: (Int, Int, Int)): Path = dir.resolve(workload).resolve(s"${c._1}-${c._2}-${c._3}.json")
  private def partsFile: Path = dir.resolve("parts.json")

  /** The parts recorded so far, in order. */
  def parts: Seq[Part] = if (!Files.isRegularFile(partsFile)) Seq.empty else {
    val j = try ujson.read(Files.readAllBytes(partsFile)) catch { case e: Exception => MapmError.fail(s"$partsFile: unreadable (${e.getMessage})") }
    try j.arr.toSeq.map(p => Part(p("index").num.toInt, p("started").str, p("wallSeconds").num, p("jobs").num.toInt, p("cores").num.toInt,
      p("runs").num.toInt))
    catch { case e: NoSuchElementException => MapmError.fail(s"$partsFile: a part lacks a field (${e.getMessage})") }
  }

  /** Records `p` (replacing the part of the same index). */
  def savePart(p: Part): Unit = synchronized {
    val all = parts.filterNot(_.index == p.index) :+ p
    atomicWrite(partsFile, ujson.write(ujson.Arr.from(all.sortBy(_.index).map(_.json)), indent = 2))
  }

  /** Keeps a passed run's `result.json` and `stats.json` (from its run folder `runDir`) under `key`. */
  def save(workload: String, c: (Int, Int, Int), key: String, part: Int, runDir: Path): Unit = {
    val record = ujson.Obj("key" -> key, "part" -> part,
      "result" -> ujson.read(Files.readAllBytes(runDir.resolve("result.json"))),
      "stats" -> ujson.read(Files.readAllBytes(runDir.resolve("stats.json"))))
    atomicWrite(file(workload, c), ujson.write(record, indent = 1))
  }

  /** Puts the record of (workload, c) back into its run folder `runDir` when one exists under
    * `key`, so the results are read as if the run had just finished; whether it did. */
  def restore(workload: String, c: (Int, Int, Int), key: String, runDir: Path): Boolean = {
    val f = file(workload, c)
    Files.isRegularFile(f) && {
      val j = try ujson.read(Files.readAllBytes(f)) catch { case e: Exception => MapmError.fail(s"$f: unreadable (${e.getMessage})") }
      j.obj.get("key").exists(_.strOpt.contains(key)) && {
        val stats = ujson.write(j.obj.getOrElse("stats", ujson.Null), indent = 2)
        HarnessStats.parse(stats, s"$f (its stats)") // a damaged record fails here, naming its file
        MapmError.check(j.obj.get("result").exists(_.objOpt.isDefined), s"$f: no result object")
        Files.createDirectories(runDir)
        atomicWrite(runDir.resolve("stats.json"), stats)
        atomicWrite(runDir.resolve("result.json"), ujson.write(j("result"), indent = 2))
        true
      }
    }
  }

  /** The harness stats of the kept run of (workload, c), whatever its key: the figures of another
    * full run (other code or options), shown beside this one's and never taken as this one's. */
  def keptStats(workload: String, c: (Int, Int, Int)): Option[HarnessStats] = {
    val f = file(workload, c)
    if (!Files.isRegularFile(f)) None else {
      val j = try ujson.read(Files.readAllBytes(f)) catch { case e: Exception => MapmError.fail(s"$f: unreadable (${e.getMessage})") }
      Some(HarnessStats.parse(ujson.write(j.obj.getOrElse("stats", ujson.Null)), s"$f (its stats)"))
    }
  }

  /** Removes every record and part (a fresh full run). */
  def clear(): Unit = if (Files.isDirectory(dir)) {
    val all = Files.walk(dir).iterator.asScala.toSeq.sortBy(-_.getNameCount)
    all.foreach(Files.delete)
  }
}

object RunArchive {
  /** One part of an evaluation run in parts: when it started, its wall seconds, `--jobs`, the
    * machine's cores and the runs it finished. */
  final case class Part(index: Int, started: String, wallSeconds: Double, jobs: Int, cores: Int, runs: Int) {
    def json: ujson.Obj = ujson.Obj("index" -> index, "started" -> started, "wallSeconds" -> wallSeconds, "jobs" -> jobs,
      "cores" -> cores, "runs" -> runs)
  }

  /** The archive beside results page `page`. */
  def beside(page: Path): RunArchive =
    new RunArchive(Option(page.toAbsolutePath.getParent).getOrElse(page.toAbsolutePath).resolve("results").resolve("runs"))

  /** A hash of the sources that decide a run's figures: everything under src/main/scala/mapm but
    * the command line's, the cost orchestration's and the evaluation's own (the hardware, the model, the record formats, the simulation driver) and
    * the C++ harness. */
  def codeHash: String = {
    val roots = Seq("src/main/scala/mapm", "tools/harness").map(Harness.root.resolve)
    val skip = Seq("cli", "costflow", "evaluation").map(p => Harness.root.resolve(s"src/main/scala/mapm/$p"))
    val files = roots.flatMap(r => Files.walk(r).iterator.asScala.filter(f => Files.isRegularFile(f) && !skip.exists(f.startsWith)))
      .sortBy(_.toString)
    Verilator.hash(files.map(f => Harness.root.relativize(f).toString + new String(Files.readAllBytes(f), UTF_8)): _*)
  }

  /** The key of configuration `c` run on the scene file `scene` (relative to the checkout) with
    * the options `settings` (their text, every option but the output folder and the worker
    * threads, which do not change a figure): the code, the scene file's text, the settings. */
  def key(code: String, scene: String, settings: String, c: (Int, Int, Int)): String = {
    val text = new String(Files.readAllBytes(Harness.root.resolve(scene)), UTF_8)
    Verilator.hash(code, scene, text, settings, c.toString)
  }

  private def atomicWrite(f: Path, text: String): Unit = {
    Files.createDirectories(f.getParent)
    val tmp = f.resolveSibling(f.getFileName.toString + ".tmp")
    Files.write(tmp, text.getBytes(UTF_8))
    Files.move(tmp, f, StandardCopyOption.REPLACE_EXISTING, StandardCopyOption.ATOMIC_MOVE)
  }
}
