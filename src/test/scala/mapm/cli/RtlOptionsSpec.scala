package mapm.cli

import mapm.numerics.FloatFormat
import org.scalatest.funsuite.AnyFunSuite

/** The options `render` and `sweep` share, as the command line parses them: every option left
  * out takes the default that docs/harness.md states, and given ones reach the harness options. */
class RtlOptionsSpec extends AnyFunSuite {
  private def parse(args: String*): RtlOptions =
    Args.rtlOptionsParser.constructEither(args, allowPositional = false, nameMapper = mainargs.Util.kebabCaseNameMapper)
      .fold(e => fail(s"parse error: $e"), identity)

  test("no option: the documented defaults") {
    val o = parse()
    assert(o.scene == "test-scenes/cornell-box/scene.json" && o.format.isEmpty && o.g == 3 && o.out == "out")
    val h = o.harness()
    assert((h.latency, h.latencyMax, h.bandwidth, h.seed, h.maxCycles, h.clockGhz, h.simThreads) == (100, 0, 14.0, 1L, 0L, 1.5, 1))
    assert((h.queryGap, h.reqStall, h.respGap) == (0.0, 0.0, 0.0) && h.wave.isEmpty)
  }

  test("given options reach the harness options under their kebab-case names") {
    val o = parse("--latency", "7", "--latency-max", "9", "--query-gap", "0.25", "--seed", "42", "-g", "0", "--format", "fp16")
    val h = o.harness()
    assert((h.latency, h.latencyMax, h.queryGap, h.seed) == (7, 9, 0.25, 42L))
    assert(o.g == 0 && o.format.contains(FloatFormat.fp16))
  }

  test("the query order defaults to the hierarchy's: Morton for the scalable one, the host's for Table 4.2's") {
    assert(RtlOptions().settings().queryOrder == mapm.model.QueryOrder.Morton)
    assert(RtlOptions(hw = HwOptions(hierarchy = mapm.params.Hierarchy.Table42)).settings().queryOrder == mapm.model.QueryOrder.Host)
    assert(parse("--hierarchy", "table4.2", "--query-order", "morton").settings().queryOrder == mapm.model.QueryOrder.Morton)
  }

  test("the key follows the options that change a run, not the output folder or worker threads") {
    val code = "c0"
    val scene = "test-scenes/cornell-box/scene-small.json"
    val base = RtlOptions(scene = scene)
    val k = mapm.evaluation.RunArchive.key(code, scene, base.settings().archiveText(scene), (2, 1, 2))
    assert(mapm.evaluation.RunArchive.key(code, scene, base.copy(out = "elsewhere", threads = 7, simThreads = 2).settings().archiveText(scene), (2, 1, 2)) == k)
    assert(mapm.evaluation.RunArchive.key(code, scene, base.copy(scene = "/abs/path/" + scene).settings().archiveText(scene), (2, 1, 2)) == k, "the scene is named relative to the checkout")
    for (other <- Seq(base.copy(latency = 101), base.copy(bandwidth = 7.0), base.copy(g = 4), base.copy(seed = 2),
      base.copy(fidelity = Some(mapm.params.Fidelity.Timing)), base.copy(format = Some(mapm.numerics.FloatFormat.fp16)),
      base.copy(hw = HwOptions(rsEntries = Some(8))), base.copy(queryOrder = Some(mapm.model.QueryOrder.Host)),
      base.copy(hw = HwOptions(hierarchy = mapm.params.Hierarchy.Table42)), base.copy(hw = HwOptions(tsL2Banks = Some(2))),
      base.copy(hw = HwOptions(soBus = Some(mapm.params.SoBus.Ring)))))
      assert(mapm.evaluation.RunArchive.key(code, scene, other.settings().archiveText(scene), (2, 1, 2)) != k, other.toString)
    assert(mapm.evaluation.RunArchive.key(code, scene, base.settings().archiveText(scene), (2, 1, 3)) != k)
    assert(mapm.evaluation.RunArchive.key("c1", scene, base.settings().archiveText(scene), (2, 1, 2)) != k)
    assert(mapm.evaluation.RunArchive.key(code, "test-scenes/cornell-box/scene.json", base.settings().archiveText("test-scenes/cornell-box/scene.json"), (2, 1, 2)) != k)
  }

  test("toArgs gives back the options it was made from (the arguments a Slurm task reruns with), over 200 seeded draws") {
    import mapm.params.Fidelity
import mapm.pipeline.CacheSpec
    val rnd = new scala.util.Random(11)
    def pick[T](xs: T*): T = xs(rnd.nextInt(xs.size))
    def maybe[T](x: => T): Option[T] = if (rnd.nextBoolean()) Some(x) else None
    def spec = pick(CacheSpec(Some(8192)), CacheSpec(Some(32768), Some(64)), CacheSpec(Some(65536), Some(32), Some(4)),
      CacheSpec(Some(524288), Some(64), Some(CacheSpec.Full)))
    for (_ <- 0 until 200) {
      val hw = HwOptions(maybe(rnd.nextInt(512) + 1), maybe(8 * (rnd.nextInt(4) + 1)), maybe(spec), maybe(spec), maybe(spec), maybe(spec),
        maybe(spec), maybe(rnd.nextInt(64) + 1), pick(mapm.params.Hierarchy.all: _*), maybe(pick(1, 2, 4, 16)), maybe(pick(1, 2, 8)),
        mainargs.Flag(rnd.nextBoolean()), soBus = maybe(pick(mapm.params.SoBus.all: _*)))
      val o = RtlOptions(scene = pick("test-scenes/cornell-box/scene.json", "a b/c.json"), format = maybe(pick(FloatFormat.fp16, FloatFormat(5, 4), FloatFormat.fp64)),
        layout = pick(mapm.format.SlotLayout.Packed, mapm.format.SlotLayout.Wide), g = rnd.nextInt(5), arith = pick(mapm.numerics.Arith.Online, mapm.numerics.Arith.Conventional),
        fidelity = maybe(pick(Fidelity.Full, Fidelity.Timing)), latency = rnd.nextInt(300), latencyMax = rnd.nextInt(400),
        queryGap = pick(0.0, 0.1, 1.0 / 3), reqStall = rnd.nextDouble(), respGap = pick(0.0, 0.25), tailProb = pick(0.0, 0.01),
        tailLatency = rnd.nextInt(5000), bandwidth = pick(14.0, 3.5, 1e-3), clockGhz = pick(1.5, 0.319), seed = rnd.nextLong() & Long.MaxValue,
        simThreads = rnd.nextInt(4) + 1, maxCycles = rnd.nextInt(1000000).toLong, out = pick("out", "x/y"), threads = rnd.nextInt(8) + 1,
        queryOrder = maybe(pick(mapm.model.QueryOrder.all: _*)), hw = hw)
      assert(parse(Args.toArgs(o): _*) == o, Args.toArgs(o).mkString(" "))
    }
  }
}
