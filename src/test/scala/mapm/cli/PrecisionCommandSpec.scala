package mapm.cli

import java.nio.file.{Files, Path}

import mapm.Slow
import mapm.numerics.FloatFormat
import mapm.params.Fidelity
import org.scalatest.funsuite.AnyFunSuite

/** `tools/mapm precision` end to end on the small Cornell frame at e5m4 (online, g = 3): its
  * PSNR against what `model` reports for the same frame (another path through the model), its
  * frame cycles at 1/1/1 against a timing-fidelity `render --bare`, its unit figures against the
  * cost flow's report, and a second run that takes every point from the first. */
@Slow
class PrecisionCommandSpec extends AnyFunSuite {
  private val small = "test-scenes/cornell-box/scene-small.json"

  test("precision at e5m4 on the small frame: PSNR as model reports it, cycles as render's, figures as the cost flow's; a rerun resumes") {
    assume(mapm.testutil.HostTools.onPath("verilator"), "verilator is not on PATH")
    val out = Files.createTempDirectory("mapm-precision")
    val args = Seq("--formats", "5,4", "--arith", "online", "--scene", small, "--frame-at", "1/1/1", "--out", out.toString)
    assert(PrecisionCommand.run(args) == 0)
    val csv = Files.readAllLines(out.resolve("precision.csv")).toArray.map(_.toString)
    assert(csv.length == 2 && Files.size(out.resolve("precision-pareto.png")) > 1000)
    val row = csv.head.split(',').zip(csv(1).split(',')).toMap
    assert(row("point") == "e5m4-online-g3" && row("pareto") == "true")

    // The model command's PSNR of the same frame in the same format and guard digits.
    assert(ModelCommand.run(Seq("--scene", small, "--format", "5,4", "--out", out.resolve("model").toString)) == 0)
    val stats = ujson.read(Files.readAllBytes(out.resolve("model").resolve("cornell-box-scene-small-stats.json")))
    assert(math.abs(row("psnr_db").toDouble - stats("psnrIndirectVsFloat64").num) < 1e-3, s"${row("psnr_db")} against $stats")
    val flip = row("flip").toDouble
    assert(flip > 0 && flip < 1)

    // The frame's cycles at 1/1/1: a timing-fidelity render of the bare MAPM.
    val r = out.resolve("render")
    assert(RenderCommand.render(tsm = 1, som = 1, soa = 1, bare = mainargs.Flag(true), options = RtlOptions(scene = small,
      format = Some(FloatFormat(5, 4)), fidelity = Some(Fidelity.Timing), out = r.toString, threads = 2)) == 0)
    val rstats = ujson.read(Files.readAllBytes(Files.walk(r).filter(_.getFileName.toString.endsWith("stats.json"))
      .filter(p => ujson.read(Files.readAllBytes(p)).obj.contains("cycles")).findFirst.get))
    assert(row("frame_cycles").toLong == rstats("cycles").num.toLong && row("frame_config") == "1/1/1")

    // The SOA's figures: the cost flow's cached report for the unit.
    val soa = mapm.costflow.UnitCostCache.get("soa", FloatFormat(5, 4), 3, mapm.numerics.Arith.Online, _ => ())
    assert(math.abs(row("soa_nj_per_op").toDouble - soa.energyPerOpNj) < 1e-4 && math.abs(row("soa_area_um2").toDouble - soa.areaUm2) < 1)

    // A second run takes the point from the first (its record untouched).
    val point: Path = out.resolve("points").resolve("e5m4-online-g3.json")
    val before = Files.getLastModifiedTime(point)
    assert(PrecisionCommand.run(args) == 0 && Files.getLastModifiedTime(point) == before)
  }
}
