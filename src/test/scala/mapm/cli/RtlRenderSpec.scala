package mapm.cli

import mapm.Slow
import scala.jdk.CollectionConverters._
import java.nio.file.{Files, Path, Paths}

import mapm.model.TestScenes
import org.scalatest.funsuite.AnyFunSuite

/** End to end: `render` of a tiny Cornell-box frame through the emitted whole-MAPM RTL in
  * Verilator at 1/1/1 and 2/1/2: every SO checked against the model bit for bit (in the harness),
  * the frame bit-equal to the model frame, the TS-op count equal to the model's. */
@Slow
class RtlRenderSpec extends AnyFunSuite {
  private def haveVerilator: Boolean =
    mapm.testutil.HostTools.onPath("verilator")

  private lazy val scene: Path = {
    val dir = Paths.get("target/rtl-render-test")
    Files.createDirectories(dir)
    val obj = TestScenes.cornellObj.toAbsolutePath.toString.replace("\\", "\\\\")
    val text =
      s"""{ "obj": "$obj",
         |  "camera": { "position": [278, 273, -530], "direction": [0, 0, 1], "up": [0, 1, 0], "fov": 39.3 },
         |  "lights": [ { "type": "point", "position": [1, 25, 1], "power": [10000000, 10000000, 10000000] } ],
         |  "width": 8, "height": 6, "finalGatherRays": 4, "photons": 200, "maxBounces": 3, "h": { "auto": 20 }, "seed": 3 }""".stripMargin
    Files.write(dir.resolve("tiny.json"), text.getBytes("UTF-8"))
  }

  for ((t, s, a, seed, bare) <- Seq((1, 1, 1, 1L, false), (2, 1, 2, 7L, true)))
    test(s"render through the RTL at $t/$s/$a${if (bare) " --bare (the harness adds the colours)" else " (the coprocessor writes the frame buffer)"}") {
    assume(haveVerilator, "verilator is not on PATH: the RTL render test needs it")
    val out = Paths.get(s"target/rtl-render-test/out-$t-$s-$a")
    assert(RenderCommand.render(tsm = t, som = s, soa = a, bare = mainargs.Flag(bare),
      options = RtlOptions(scene = scene.toString, seed = seed, maxCycles = 2000000, out = out.toString, threads = 2)) == 0)
    val stats = ujson.read(Files.readAllBytes(out.resolve("rtl-render-test-tiny-rtl-stats.json")))
    assert(stats("result").str == "PASS")
    assert(stats("frameEqualsModel").bool)
    assert(stats("frameSource").str == (if (bare) "harness accumulation" else "hardware frame buffer"))
    assert(stats("soIssued").num == stats("modelShaderOps").num && stats("soIssued").num > 0)
    assert(stats("soPassingCond").num == stats("modelShaderOpsPassingCond").num)
    assert(stats("tsOps").num == stats("modelTsOps").num)
    // Each counter says what it counts: the TSMs' stalls are TSM-cycles (summed over the TSMs).
    assert(stats("counterUnits")("stallRsFull").str == "TSM-cycles" && stats("counterUnits")("cycles").str == "cycles")
    assert(Files.isRegularFile(out.resolve("rtl-render-test-tiny-rtl.png")) && Files.isRegularFile(out.resolve("rtl-render-test-tiny-rtl.pfm")))
  }

  test("--query-order morton: another stream, the same frame and the same shader operations, every one checked") {
    assume(haveVerilator, "verilator is not on PATH: the RTL render test needs it")
    def run(order: mapm.model.QueryOrder): Path = {
      val out = Paths.get(s"target/rtl-render-test/out-order-$order")
      assert(RenderCommand.render(tsm = 2, som = 1, soa = 2,
        options = RtlOptions(scene = scene.toString, seed = 7, maxCycles = 2000000, out = out.toString, threads = 2, queryOrder = Some(order))) == 0)
      out
    }
    val (host, morton) = (run(mapm.model.QueryOrder.Host), run(mapm.model.QueryOrder.Morton))
    def bytes(dir: Path, f: String) = Files.readAllBytes(dir.resolve("rtl-render-test-tiny-rtl").resolve(f)).toSeq
    val (hi, mi) = (bytes(host, "image.bin"), bytes(morton, "image.bin"))
    assert(hi.size == mi.size && hi != mi, "the images differ in the order of their query records alone")
    assert(bytes(host, "frame.f64") == bytes(morton, "frame.f64"), "the harness's frames are bit-equal")
    val Seq(hs, ms) = Seq(host, morton).map(o => ujson.read(Files.readAllBytes(o.resolve("rtl-render-test-tiny-rtl-stats.json"))))
    for (k <- Seq("soIssued", "soPassingCond", "tsOps", "queries")) assert(hs(k).num == ms(k).num, k)
    // The harness checked every SO of each run against the model's (q, photon) list: none lost,
    // duplicated or unexpected, so both runs gave the same multiset of results.
    assert(ms("result").str == "PASS" && ms("frameEqualsModel").bool)
  }

  test("render --wave writes an FST of the chosen cycle window and names it; --max-cycles is a stop reported as such") {
    assume(haveVerilator, "verilator is not on PATH: the RTL render test needs it")
    val out = Paths.get("target/rtl-render-test/out-wave")
    val wave = out.resolve("tiny.fst")
    Files.createDirectories(out)
    Files.deleteIfExists(wave)
    val printed = new java.io.ByteArrayOutputStream
    assert(Console.withOut(printed)(RenderCommand.render(tsm = 1, som = 1, soa = 1, wave = Some(wave.toString), waveStart = 100,
      waveEnd = Some(400), options = RtlOptions(scene = scene.toString, seed = 1, out = out.toString, threads = 2))) == 0)
    val bytes = Files.readAllBytes(wave)
    assert(bytes.length > 1000, "an FST with the window's signal changes")
    assert(printed.toString("UTF-8").contains(s"wrote ${wave.toAbsolutePath} (FST waveform of cycles 100 to 400"), printed)
    // Stopped at 500 cycles as asked: exit 0, the stop said, nothing claimed to differ, no image.
    Files.list(out).iterator.asScala.filter(_.toString.endsWith(".png")).foreach(Files.delete)
    val stopped = new java.io.ByteArrayOutputStream
    assert(Console.withOut(stopped)(RenderCommand.render(tsm = 1, som = 1, soa = 1,
      options = RtlOptions(scene = scene.toString, seed = 5, maxCycles = 500, out = out.toString, threads = 2))) == 0)
    val text = stopped.toString("UTF-8")
    assert(text.contains("per-SO check: STOPPED at cycle 500 as asked (--max-cycles 500)") && text.contains("not compared"), text)
    assert(!text.contains("DIFFERENT") && !text.contains("FAIL") && !text.contains("PSNR of the RTL"), text)
    assert(!Files.list(out).iterator.asScala.exists(_.toString.endsWith(".png")), "no image of an unfinished frame")
    val stats = ujson.read(Files.readAllBytes(out.resolve("rtl-render-test-tiny-rtl-stats.json")))
    assert(stats("result").str == "STOPPED" && stats("stoppedAtMaxCycles").bool && stats("frameEqualsModel").isNull && stats("cycles").num == 500)
  }
}
