package mapm.top

import java.nio.file.{Files, Paths}

import chisel3._
import chiseltest._
import mapm.Slow
import mapm.params._
import mapm.top.Mapm
import mapm.format.{ExpectedSoFile, MemoryImage}
import mapm.memory.{DramModel, DramTiming, MemImage}
import mapm.model.{Frame, SceneConfig, TestScenes}
import mapm.numerics.FloatFormat
import mapm.sim.ExpectedSo
import mapm.testutil.Sim
import org.scalatest.funsuite.AnyFunSuite
import scala.collection.mutable
import scala.util.Random

/** The whole MAPM in chiseltest, driven cycle by cycle from Scala against the model: the
  * behavioural DRAM ([[DramModel]]: random latency per request, random request back-pressure,
  * random response order and gaps, protocol checks on every handshake) plays the memory, the
  * query stream has random gaps, and every result port is read every cycle. The multiset of
  * (query, photon, colour bits, flags, cond) must equal the model's ([[ExpectedSo]]: the tree
  * search, [[mapm.numerics.ShaderChainModel]] and [[mapm.numerics.CondModel]]), and the counters its
  * counts. A run that makes no progress for 5,000 cycles fails instead of hanging. */
@Slow
class MapmSystemSpec extends AnyFunSuite with Sim {
  import MapmSystemSpec.Case
  private val dir = Paths.get("target/mapm-system-test")


  private def prepare(photons: Int, radius: String, fmt: FloatFormat, g: Int): Case = {
    Files.createDirectories(dir)
    val obj = TestScenes.cornellObj.toAbsolutePath.toString
    val json =
      s"""{ "obj": "$obj", "camera": { "position": [278, 273, -530], "direction": [0, 0, 1], "up": [0, 1, 0], "fov": 39.3 },
         |  "lights": [ { "type": "point", "position": [1, 25, 1], "power": [10000000, 10000000, 10000000] } ],
         |  "width": 4, "height": 3, "finalGatherRays": 3, "photons": $photons, "maxBounces": 4, "h": $radius, "seed": 9,
         |  "directLightSamples": 0 }""".stripMargin
    val sceneFile = Files.write(dir.resolve(s"p$photons-${fmt.name}.json"), json.getBytes("UTF-8"))
    val frame = Frame.prepare(SceneConfig.load(sceneFile), fmt, 2)
    val image = mapm.sim.FrameImage.of(frame.map, frame.querySet)
    val file = dir.resolve(s"p$photons-${fmt.name}-expected.bin")
    val res = ExpectedSo.write(frame.map, frame.querySet, g, frame.width, frame.height, file, 2)
    val expected = ExpectedSoFile.read(file).rows.map(r => (r.query, r.photon) -> (r.colour, r.flags, r.cond))
    assert(expected.size == res.count)
    assert(expected.map(_._1).distinct.size == expected.size, "the model yields each (query, photon) once")
    // Padded to whole 64-byte lines: the caches fetch whole lines.
    val bytes = java.util.Arrays.copyOf(image.toBytes, ((image.totalBytes + 127) / 64 * 64).toInt)
    Case(image, bytes, expected.toMap, res.tsOps, res.passing)
  }

  private def run(c: Mapm, k: Case, seed: Long, timing: DramTiming, queryGap: Double): Unit = {
    val rnd = new Random(seed)
    val img = k.image
    c.clock.setTimeout(0)
    c.io.cfg.h.poke(img.h.U)
    c.io.cfg.nodeBase.poke(img.nodeBase.U)
    c.io.cfg.photonBase.poke(img.photonBase.U)
    c.io.cfg.queryBase.poke(img.queryBase.U)
    c.io.cfg.nodeCount.poke(img.nodeCount.U)
    c.io.query.valid.poke(false.B)
    c.io.mem.resp.valid.poke(false.B)
    c.io.room.foreach(_.poke(Mapm.resultRoom(c.p).U))
    c.reset.poke(true.B); c.clock.step(2); c.reset.poke(false.B)
    val dram = new DramModel(c.io.mem, new MemImage(k.bytes), timing, rnd)
    val seen = mutable.Map[(Int, Int), (Seq[Long], Seq[Int], Boolean)]()
    var fed = 0
    var idle = 0
    var cycles = 0L
    var finished = false
    while (!finished) {
      val offer = fed < img.stream.length && rnd.nextDouble() >= queryGap
      c.io.query.valid.poke(offer.B)
      if (offer) {
        val q = img.stream(fed)
        c.io.query.bits.q.poke(q.U)
      }
      dram.drive()
      var progress = false
      if (offer && c.io.query.ready.peek().litToBoolean) { fed += 1; progress = true }
      for (o <- c.io.out if o.valid.peek().litToBoolean) {
        val key = (o.bits.q.peek().litValue.toInt, o.bits.photon.peek().litValue.toInt)
        val got = (o.bits.colour.map(_.peek().litValue.toLong).toSeq, o.bits.flags.map(_.peek().litValue.toInt).toSeq, o.bits.cond.peek().litToBoolean)
        assert(k.expected.contains(key), s"seed $seed: unexpected SO $key")
        assert(!seen.contains(key), s"seed $seed: SO $key reported twice")
        assert(got == k.expected(key), s"seed $seed: SO $key: got $got, expected ${k.expected(key)}")
        seen(key) = got
        progress = true
      }
      assert(!c.io.error.peek().litToBoolean, s"seed $seed: io.error raised")
      finished = fed == img.stream.length && c.io.done.peek().litToBoolean && dram.outstanding == 0
      progress = dram.observe() || progress
      c.clock.step()
      cycles += 1
      idle = if (progress) 0 else idle + 1
      assert(idle < 5000, s"seed $seed: no progress for 5,000 cycles ($fed queries fed, ${seen.size} of ${k.expected.size} SOs seen)")
    }
    assert(seen.size == k.expected.size, s"seed $seed: ${k.expected.size - seen.size} SOs missing")
    val cnt = c.io.counters
    assert(cnt.tsOps.peek().litValue == k.tsOps && cnt.soIssued.peek().litValue == k.expected.size && cnt.soPassed.peek().litValue == k.passing)
    assert(cnt.queries.peek().litValue == img.stream.length)
  }

  test("1/1/1 fp32: 150 photons against the model, 8 seeds of random DRAM latency 0-300, back-pressure and query gaps") {
    val k = prepare(150, """{ "auto": 15 }""", FloatFormat.fp32, 3)
    assert(k.expected.size > 200)
    simulate(new Mapm(MapmParams.small)) { c =>
      for (seed <- 1 to 8) run(c, k, seed, DramTiming(maxLatency = if (seed % 2 == 0) 300 else 30, reqReady = 0.7, respValid = 0.6), queryGap = 0.3)
    }
    info(s"${k.image.queryCount} queries, ${k.expected.size} SOs, ${k.tsOps} TS ops per seed")
  }

}

object MapmSystemSpec {
  /** A tiny Cornell-box frame: the memory image (and its bytes) and the expected SOs by (q, photon). */
  final case class Case(image: MemoryImage, bytes: Array[Byte], expected: Map[(Int, Int), (Seq[Long], Seq[Int], Boolean)],
                        tsOps: Long, passing: Long)
}
