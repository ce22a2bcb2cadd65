package mapm.evaluation

import java.nio.charset.StandardCharsets.UTF_8
import java.nio.file.{Files, Path, Paths}

import mapm.MapmError
import mapm.sim.HarnessStats
import org.scalatest.funsuite.AnyFunSuite

/** The evaluation's run archive ([[RunArchive]]): a kept run comes back into its run folder byte
  * for byte in its figures, only under its own key; parts add up; the key follows every option
  * that changes a run and ignores those that do not. */
class RunArchiveSpec extends AnyFunSuite {
  private val work = Paths.get("target/run-archive-test")

  private def fresh(name: String): Path = {
    val d = work.resolve(name)
    if (Files.exists(d)) Files.walk(d).sorted(java.util.Comparator.reverseOrder()).forEach(f => Files.delete(f))
    Files.createDirectories(d)
  }

  /** A run folder as a finished run leaves it: result.json and the harness's stats.json. */
  private def runFolder(dir: Path, cycles: Long): Path = {
    Files.createDirectories(dir)
    SweepReport.writeResult(dir, SweepReport.TaskResult("2/1/2", 2, 1, 2, passed = true, "", Seq("simulation" -> 12.5)))
    val stats = mapm.testutil.StatsFixture.json(cycles, 3 * cycles, 2 * cycles, 448, 7)
    Files.write(dir.resolve("stats.json"), ujson.write(stats).getBytes(UTF_8))
    HarnessStats.read(dir.resolve("stats.json")) // the fixture is a valid stats file
    dir
  }

  test("a kept run is restored under its key only, with the same result and figures") {
    val d = fresh("restore")
    val archive = new RunArchive(d.resolve("runs"))
    archive.save("cornell-2k", (2, 1, 2), "k1", 1, runFolder(d.resolve("ran"), 1000))
    val back = d.resolve("back")
    assert(!archive.restore("cornell-2k", (2, 1, 2), "k2", back), "another key is another run")
    assert(!archive.restore("cornell-8k", (2, 1, 2), "k1", back), "another workload")
    assert(!archive.restore("cornell-2k", (2, 1, 3), "k1", back), "another configuration")
    assert(!Files.exists(back))
    assert(archive.restore("cornell-2k", (2, 1, 2), "k1", back))
    val ran = HarnessStats.read(d.resolve("ran/stats.json"))
    val again = HarnessStats.read(back.resolve("stats.json"))
    assert(again == ran)
    assert(ujson.read(Files.readAllBytes(back.resolve("result.json"))) == ujson.read(Files.readAllBytes(d.resolve("ran/result.json"))))
  }

  test("restore through a sweep's run folder gives the row the run gave") {
    val d = fresh("row")
    val archive = new RunArchive(d.resolve("runs"))
    val workA = d.resolve("a")
    archive.save("sponza-atrium", (2, 1, 2), "k", 3, runFolder(SweepReport.configDir(workA, (2, 1, 2)), 123456))
    val workB = d.resolve("b")
    assert(archive.restore("sponza-atrium", (2, 1, 2), "k", SweepReport.configDir(workB, (2, 1, 2))))
    val (a, b) = (SweepReport.readRow(workA, (2, 1, 2)), SweepReport.readRow(workB, (2, 1, 2)))
    assert(b.passed && b.stats.map(_.cycles).contains(123456L))
    assert(a == b)
  }

  test("a damaged record is a one-line error naming its file") {
    val d = fresh("damaged")
    val archive = new RunArchive(d.resolve("runs"))
    Files.createDirectories(d.resolve("runs/cornell-2k"))
    Files.write(d.resolve("runs/cornell-2k/2-1-2.json"), "{\"key\": \"k\", \"result\": {}, \"stats\": {\"top\": 1}}".getBytes(UTF_8))
    val e = intercept[MapmError](archive.restore("cornell-2k", (2, 1, 2), "k", d.resolve("back")))
    assert(e.getMessage.contains("2-1-2.json") && !e.getMessage.contains("\n"), e.getMessage)
    assert(!Files.exists(d.resolve("back")), "nothing restored")
    Files.write(d.resolve("runs/cornell-2k/2-1-2.json"), "{not json".getBytes(UTF_8))
    val e2 = intercept[MapmError](archive.restore("cornell-2k", (2, 1, 2), "k", d.resolve("back")))
    assert(e2.getMessage.contains("2-1-2.json"), e2.getMessage)
  }

  test("parts are replaced by index and kept in order; clear removes records and parts") {
    val d = fresh("parts")
    val archive = new RunArchive(d.resolve("runs"))
    assert(archive.parts.isEmpty)
    val p1 = RunArchive.Part(1, "2026-12-04T18:00Z", 100.0, 2, 2, 3)
    archive.savePart(p1)
    archive.savePart(RunArchive.Part(2, "2026-12-05T09:00Z", 50.0, 2, 2, 1))
    archive.savePart(p1.copy(wallSeconds = 250.5, runs = 7))
    assert(archive.parts == Seq(p1.copy(wallSeconds = 250.5, runs = 7), RunArchive.Part(2, "2026-12-05T09:00Z", 50.0, 2, 2, 1)))
    // the page states the sum and each part
    val text = ResultsDoc.wall(archive.parts)
    assert(text.contains(f"${250.5 + 50.0}%.0f s wall in 2 parts") && text.contains("part 1: 7 runs in ") && text.contains("part 2: 1 runs in 50 s"), text)
    assert(ResultsDoc.wall(Seq(p1)) == ", 100 s wall with --jobs 2 on a 2-core machine")
    archive.save("cornell-2k", (2, 1, 2), "k", 1, runFolder(d.resolve("ran"), 10))
    archive.clear()
    assert(archive.parts.isEmpty && !archive.restore("cornell-2k", (2, 1, 2), "k", d.resolve("back")))
  }
}
