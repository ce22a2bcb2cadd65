package mapm.cli

import java.io.ByteArrayOutputStream
import java.nio.file.{Files, Paths}

import mapm.{MapmError, Slow}
import org.scalatest.funsuite.AnyFunSuite

/** `mapm stress`: a short seeded sample (the CI's; the benchmark runs 100 seeds per configuration,
  * docs/harness.md), the replay of a stress run by `render` with the printed options, and the stop
  * at the first failure with the command that reproduces it. Uses the 2/1/3 build the fault spec
  * also uses. */
@Slow
class StressSpec extends AnyFunSuite {
  private val out = Paths.get("target/stress-test")

  private def csvRows(dir: java.nio.file.Path): Seq[Map[String, String]] = {
    val lines = new String(Files.readAllBytes(dir.resolve("stress.csv")), "UTF-8").linesIterator.toSeq
    val head = lines.head.split(",").toSeq
    lines.tail.map(l => head.zip(l.split(",", -1)).toMap)
  }

  test("seeds are drawn from the seed alone, within the documented ranges") {
    val a = (1 to 200).map(s => mapm.pipeline.Stress.draw(s, 1000000))
    assert(a == (1 to 200).map(s => mapm.pipeline.Stress.draw(s, 1000000)), "the same seed draws the same memory system")
    assert(a.distinct.size == 200)
    assert(a.forall(o => o.latency >= 0 && o.latency <= 40 && (o.latencyMax == 0 || o.latencyMax > o.latency)))
    assert(a.forall(o => o.queryGap < 0.6 + 1e-9 && o.reqStall <= 0.5 && o.respGap <= 0.5))
    assert(a.count(_.tailProb > 0) > 30 && a.filter(_.tailProb > 0).forall(o => o.tailLatency >= (o.latencyMax max o.latency) + 200))
    assert(a.count(_.latencyMax >= a.head.latency + 300) > 10, "some runs draw the widest latency spread")
  }

  test("configuration entries parse with an optional format; bad ones are one clear error") {
    assert(StressCommand.parseEntries("1/1/1, 2/2/2:fp16").map(_.label) == Seq("1/1/1", "2/2/2:e5m10"))
    assert(intercept[MapmError](StressCommand.parseEntries("1/1/1:fp16:x")).getMessage.contains("'1/1/1:fp16:x'"))
    // A banked run replays with its banks; a bad count is refused before any work.
    val banked = mapm.pipeline.Stress.renderCommand("s.json", StressCommand.parseEntries("3/3/2").head, 3, mapm.pipeline.Stress.draw(4, 1000000),
      0, 1, mapm.pipeline.Tuning(sopL2Banks = Some(8)))
    assert(banked.contains(" --tsm 3 --som 3 --soa 2 --g 3 --sop-l2-banks 8 "), banked)
    // A ring-bus run replays on the ring bus; an unknown bus is one clear error.
    val ring = mapm.pipeline.Stress.renderCommand("s.json", StressCommand.parseEntries("3/3/2").head, 3, mapm.pipeline.Stress.draw(4, 1000000),
      0, 1, mapm.pipeline.Tuning(soBus = Some(mapm.params.SoBus.Ring)))
    assert(ring.contains(" --so-bus ring "), ring)
    assert(intercept[MapmError](StressCommand.run(Seq("--so-bus", "crossbar"))).getMessage.contains("Data bus must be ring or serial, got 'crossbar'"))
    assert(intercept[MapmError](StressCommand.run(Seq("--sop-l2-banks", "3"))).getMessage.contains("--sop-l2-banks"))
  }

  test("three seeds of 2/1/3 pass, and render replays seed 2 cycle for cycle") {
    assume(mapm.testutil.HostTools.onPath("verilator"), "verilator is not on PATH")
    val dir = out.resolve("pass")
    assert(StressCommand.stress(seeds = 3, configs = "2/1/3", out = dir.toString, threads = 2) == 0)
    val rows = csvRows(dir)
    assert(rows.map(_("seed")) == Seq("1", "2", "3") && rows.forall(_("result") == "PASS"))
    assert(rows.map(_("so_checked")).distinct.size == 1 && rows.head("so_checked").toLong > 1000)
    val line = mapm.pipeline.Stress.renderCommand(StressCommand.defaultScene, StressCommand.parseEntries("2/1/3").head, 3,
      mapm.pipeline.Stress.draw(2, 5000000), 0, 1).split(' ').toSeq
    val args = line.drop(2).takeWhile(_ != "--wave") ++ Seq("--out", dir.resolve("replay").toString, "--threads", "2")
    val stdout = new ByteArrayOutputStream()
    assert(Console.withOut(stdout)(RenderCommand.run(args)) == 0)
    val stats = ujson.read(Files.readAllBytes(dir.resolve("replay/cornell-box-scene-small-rtl-stats.json")))
    assert(stats("cycles").num.toLong == rows(1)("cycles").toLong, s"render ${args.mkString(" ")}")
  }

  test("the first failing run stops the stress with its seed and the command that reproduces it") {
    assume(mapm.testutil.HostTools.onPath("verilator"), "verilator is not on PATH")
    val stdout = new ByteArrayOutputStream()
    val e = intercept[MapmError](Console.withOut(stdout)(
      StressCommand.stress(seeds = 5, configs = "2/1/3", maxCycles = 1000, out = out.resolve("fail").toString, threads = 2)))
    assert(e.getMessage.startsWith("stress: 2/1/3 seed 1 failed after 0 passing runs: ") && e.getMessage.contains("not finished within --max-cycles 1000"), e.getMessage)
    val text = stdout.toString("UTF-8")
    assert(text.contains("reproduce: tools/mapm render --scene test-scenes/cornell-box/scene-small.json --tsm 2 --som 1 --soa 3 ") &&
      text.contains("--seed 1 ") && text.contains("--wave stress-fail.fst --wave-start 0 --wave-end 1010"), text)
    assert(csvRows(out.resolve("fail")).map(_("result")) == Seq("FAIL"))
  }
}
