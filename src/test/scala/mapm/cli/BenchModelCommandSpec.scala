package mapm.cli

import java.nio.file.Files
import org.scalatest.funsuite.AnyFunSuite

/** `bench-model` runs the whole model pipeline and reports per run; bad options are one error.
  * (It checks what the command does, not how fast: speed figures come from running it.) */
class BenchModelCommandSpec extends AnyFunSuite {
  private def capture(body: => Int): (Int, String) = {
    val buf = new java.io.ByteArrayOutputStream()
    val code = Console.withOut(buf)(body)
    (code, buf.toString("UTF-8"))
  }

  test("one timed run of the Cornell box: per-run and per-stage lines, and the model's files") {
    val out = Files.createTempDirectory("mapm-bench-model")
    val (code, text) = capture(BenchModelCommand.run(Seq("--repeat", "1", "--warmup", "0", "--out", out.toString, "--threads", "2")))
    assert(code == 0)
    val lines = text.linesIterator.toSeq
    assert(lines.exists(_.startsWith("workload: 75x60, 36 final-gather rays, 2000 photons")), text)
    assert(lines.exists(l => l.startsWith("run 1: wall ") && l.contains("M shader ops/s")), text)
    val stages = lines.find(_.trim.startsWith("stages (s):")).getOrElse(fail(text))
    for (s <- Seq("load scene", "photon tracing", "final gather", "choose h", "quantize queries", "search+shade (format)", "write images"))
      assert(stages.contains(s), stages)
    assert(lines.last.startsWith("wall: fastest "))
    val json = ujson.read(Files.readString(out.resolve("cornell-box-stats.json")))
    assert(json("shaderOps").num == 6075186 && json("stageSeconds").obj.contains("write images"))
    assert(Files.size(out.resolve("cornell-box.png")) > 0)
  }

  test("impossible options and a missing scene are one MapmError") {
    val e1 = intercept[mapm.MapmError](BenchModelCommand.run(Seq("--repeat", "0")))
    assert(e1.getMessage.contains("--repeat must be at least 1"))
    val e2 = intercept[mapm.MapmError](BenchModelCommand.run(Seq("--warmup", "-1")))
    assert(e2.getMessage.contains("--warmup must be at least 0"))
    val e3 = intercept[mapm.MapmError](BenchModelCommand.run(Seq("--scene", "no/such.json")))
    assert(e3.getMessage.contains("scene file not found"))
  }
}
