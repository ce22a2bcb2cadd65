package mapm.sim

import scala.jdk.CollectionConverters._
import java.nio.file.{Files, Path}

import mapm.format.{ExpectedSoFile, MemoryImage, SlotLayout}
import mapm.numerics.FloatFormat
import mapm.params.MapmParams
import org.scalatest.funsuite.AnyFunSuite
import java.math.{BigDecimal => JBig}

/** The exact frame accumulation, and the Verilator harness (tools/harness) on a stand-in top
  * ([[HarnessStub]]) whose results are known: memory replies, per-SO checks and their failure
  * messages, the frame and the stats. */
class HarnessSpec extends AnyFunSuite {
  /** 2^k exactly (java.math.BigDecimal: its add and multiply without a MathContext are exact). */
  private def pow2(k: Int): JBig =
    if (k >= 0) new JBig(java.math.BigInteger.ONE.shiftLeft(k)) else new JBig(java.math.BigInteger.valueOf(5).pow(-k), -k)

  /** The exact value of format bits (exponent field 0 is zero: the formats flush subnormals). */
  private def exactValue(f: FloatFormat, bits: Long): JBig = {
    val e = f.expField(bits); val m = f.manField(bits)
    val v = if (e == 0) JBig.ZERO else new JBig(java.math.BigInteger.valueOf((1L << f.manWidth) | m)).multiply(pow2(e - f.bias - f.manWidth))
    if (f.sign(bits) == 1) v.negate else v
  }

  /** Random finite bits of `f` over its whole exponent range, some zero, some negative. */
  private def randomBits(f: FloatFormat, rnd: scala.util.Random, negative: Boolean): Long = {
    val e = if (rnd.nextInt(10) == 0) 0 else 1 + rnd.nextInt(f.expMax - 1)
    val m = rnd.nextLong() & ((1L << f.manWidth) - 1)
    val s = if (negative && rnd.nextBoolean()) 1L else 0L
    (s << (f.expWidth + f.manWidth)) | (e.toLong << f.manWidth) | m
  }

  test("the replicated units of either arithmetic, and the TSM and SOM, stay their own Verilator classes (no_inline), nothing else") {
    val sv = Seq("Mapm_t2s1a2_e8m23_g3", "SOA_e8m23_g3", "ConvSOA_e8m23", "TSA_e8m23_t54_en", "ConvTSA_e8m23_t54_a9_en",
      "FAdd_e8m23_s9", "SomLane_x", "ConvShaderChain_e8m23", "Tsm_e8m23_d256_f16_q32", "Som_e8m23_g3_a2_r8", "SoaTiming_e8m23_t46_l45",
      "TsBlock_t2_e8m23").map(m => s"module $m(\n  input clock\n);\nendmodule\n").mkString
    val lines = Harness.noInlineConfig(sv).linesIterator.toSeq
    assert(lines.head == "`verilator_config")
    assert(lines.tail == Seq("SOA_e8m23_g3", "ConvSOA_e8m23", "TSA_e8m23_t54_en", "ConvTSA_e8m23_t54_a9_en", "Tsm_e8m23_d256_f16_q32",
      "Som_e8m23_g3_a2_r8").map(m => s"""no_inline -module "$m""""))
  }

  test("ExactSum: exact in any order, rounded once like BigDecimal") {
    for ((f, seed) <- Seq(FloatFormat.fp32, FloatFormat.fp16, FloatFormat.bf16, FloatFormat(5, 6), FloatFormat.fp24).zipWithIndex) {
      val rnd = new scala.util.Random(seed)
      for (trial <- 0 until 40) {
        val n = 1 + rnd.nextInt(300)
        // narrow exponent windows make cancellation and rounding ties likely; wide ones test range
        val vals = Array.fill(n)(randomBits(f, rnd, negative = trial % 2 == 1))
        val ref = vals.map(exactValue(f, _)).foldLeft(JBig.ZERO)(_ add _)
        val orders = Seq(vals, vals.reverse, rnd.shuffle(vals.toSeq).toArray)
        val sums = orders.map { o => val s = new ExactSum(f, 2); o.foreach(s.add(1, _)); s }
        for (s <- sums) {
          assert(new JBig(s.exact(1).get.bigInteger).multiply(pow2(s.unitExp)).compareTo(ref) == 0, s"$f trial $trial")
          assert(s.toDouble(0) == 0.0)
        }
        val d = sums.map(_.toDouble(1))
        assert(d.forall(x => java.lang.Double.doubleToRawLongBits(x) == java.lang.Double.doubleToRawLongBits(d.head)))
        assert(d.head == ref.doubleValue, s"$f trial $trial: ${d.head} vs ${ref.doubleValue}")
      }
    }
  }

  test("ExactSum: ties round to even, infinities and NaN make NaN") {
    val f = FloatFormat.fp32
    // 1 + 2^-53 is a tie between 1 and 1 + 2^-52: rounds to 1; 1 + 3 * 2^-53 rounds up to 1 + 2^-51
    val s = new ExactSum(f, 3)
    s.add(0, f.encode(1.0)); s.add(0, f.encode(math.pow(2, -53)))
    assert(s.toDouble(0) == 1.0)
    s.add(1, f.encode(1.0)); s.add(1, f.encode(3 * math.pow(2, -53)))
    assert(s.toDouble(1) == 1.0 + math.pow(2, -51))
    s.add(2, f.encode(1.0)); s.add(2, 0x7f800000L)
    assert(s.toDouble(2).isNaN)
  }

  // ---- the harness on the stand-in ----

  private lazy val verilatorPresent: Boolean =
    mapm.testutil.HostTools.onPath("verilator")

  private val params = MapmParams.table48(1, 1, 2)
  private val (width, height) = (8, 6)
  private val nq = 300

  private lazy val exe: Path = stubExe(None)

  /** The harness built on a [[HarnessStub]] (reading query 7's record at `stray` when given). */
  private def stubExe(stray: Option[Long]): Path = {
    val top = HarnessStub.name(params, stray)
    val dir = Harness.root.resolve(s"target/harness-test/$top")
    Files.createDirectories(dir)
    Files.list(dir).forEach(p => Files.delete(p))
    Emit.toFile(new HarnessStub(params, stray), dir, s"$top.sv")
    Files.write(dir.resolve("mapm_config.h"), HarnessHeader(params, top).getBytes("UTF-8"))
    Harness.build(dir, top)
  }

  /** An image of `nq` queries with random contributions (fp32, some negative), pixels and a
    * shuffled stream; no photons (the stub reads only query records). */
  private lazy val image: MemoryImage = {
    val f = FloatFormat.fp32
    val rnd = new scala.util.Random(7)
    def bits(): Long = randomBits(f, rnd, negative = true) & ~(0xffL << 23) | ((100L + rnd.nextInt(56)) << 23)
    new MemoryImage(f, SlotLayout.Packed, f.encode(0.5), Array.empty, Array.empty, Array.fill(8)(Array.empty[Long]),
      Array.fill(3)(Array.fill(nq)(bits())), Array.fill(nq)(rnd.nextInt(width * height)),
      Array.fill(3)(Array.fill(nq)(f.encode(rnd.nextDouble()))), rnd.shuffle((0 until nq).toVector).toArray)
  }

  /** The stub's SOs: (q, photon, colour bits, cond) per query. */
  private def stubRecords: Seq[(Int, Int, Seq[Long], Boolean)] =
    (0 until nq).map(q => (q, q % 5, (0 until 3).map(c => image.contribution(c)(q)), q % 3 != 0))

  private def writeExpected(path: Path, recs: Seq[(Int, Int, Seq[Long], Boolean)]): Path = {
    ExpectedSoFile.write(path, FloatFormat.fp32, width, height,
      recs.map { case (q, ph, col, cond) => ExpectedSoFile.Row(q, ph, col, Seq(0, 0, 0), cond) })
    path
  }

  private def run(name: String, recs: Seq[(Int, Int, Seq[Long], Boolean)], opts: Harness.RunOptions,
                  harness: => Path = exe): Harness.Outcome = {
    assume(verilatorPresent, "verilator is not on PATH: the harness tests need it")
    val dir = Harness.root.resolve(s"target/harness-test/$name")
    Files.createDirectories(dir)
    val img = dir.resolve("image.bin"); image.write(img)
    Harness.run(harness, img, writeExpected(dir.resolve("expected.bin"), recs), dir, opts)
  }

  test("harness build: the C++ file count its progress reads from Verilator's Makefiles is the objects make compiled") {
    assume(verilatorPresent, "verilator is not on PATH: the harness tests need it")
    val obj = exe.getParent.resolve("obj")
    val objects = Files.list(obj).iterator.asScala.count(_.toString.endsWith(".o"))
    assert(objects >= 3 && BuildProgress.units(obj, HarnessStub.name(params, None)) == objects)
  }

  test("harness: every SO checked, exact frame, stats (stand-in top, 100-cycle memory)") {
    val o = run("pass", stubRecords, Harness.RunOptions(seed = 3))
    assert(o.passed, o.verdict)
    assert(o.verdict == "PASS seed=3")
    val ref = Array.fill(3 * width * height)(JBig.ZERO)
    for ((q, _, col, cond) <- stubRecords if cond; c <- 0 until 3)
      ref(3 * image.pixel(q) + c) = ref(3 * image.pixel(q) + c).add(exactValue(FloatFormat.fp32, col(c)))
    val frame = o.frame.get
    assert(frame.length == ref.length)
    for (i <- ref.indices) assert(frame(i) == ref(i).doubleValue, s"frame value $i")
    val s = o.stats.get
    assert(s.soIssued == nq && s.soPassingCond == stubRecords.count(_._4))
    assert(s.queries == nq && s.queriesCompleted == nq)
    assert(s.bytesFetched == 32 * nq && s.memoryRequests == nq)
    assert(s.cycles > 100 * nq, "one query at a time waits for the 100-cycle memory")
    assert(s.counters("queries") == nq && s.tsOps.contains(nq.toLong))
    assert(s.caches("soq").misses == nq && s.caches("soq").hitRate == 0)
    assert(s.stallCycles("stallQuery") > 0)
    assert(math.abs(s.gbPerSecond - s.bytesPerCycle * 1.5) < 1e-9)
  }

  test("harness: latency and bandwidth shape the run") {
    val fast = run("fast", stubRecords, Harness.RunOptions(latency = 0, bandwidth = 64))
    val slow = run("slow", stubRecords, Harness.RunOptions(latency = 0, bandwidth = 2))
    assert(fast.passed && slow.passed, fast.verdict + slow.verdict)
    // 32 bytes per query at 2 bytes per cycle: at least 16 cycles per query
    assert(slow.stats.get.cycles >= 16 * nq)
    assert(fast.stats.get.cycles < 8 * nq)
  }

  test("harness: a wrong colour, a missing and an unexpected SO each FAIL with a clear reason; --max-cycles is a stop, not a failure") {
    val recs = stubRecords
    val wrong = recs.updated(17, recs(17).copy(_3 = recs(17)._3.updated(1, recs(17)._3(1) ^ 1)))
    val o1 = run("wrong", wrong, Harness.RunOptions(seed = 5))
    assert(!o1.passed && o1.verdict.startsWith("FAIL seed=5: mismatch SO (q=17, photon=2)"), o1.verdict)
    assert(o1.verdict.contains("expected colour"), o1.verdict)
    val o2 = run("missing", recs :+ ((17, 4, recs(17)._3, true)), Harness.RunOptions())
    assert(!o2.passed && o2.verdict.contains("1 expected SOs never came out (first: q=17, photon=4)"), o2.verdict)
    val o3 = run("unexpected", recs.filterNot(_._1 == 40), Harness.RunOptions())
    assert(!o3.passed && o3.verdict.contains("unexpected SO (q=40, photon=0)"), o3.verdict)
    val outs = Files.createDirectories(Harness.root.resolve("target/harness-test/stop")).resolve("results.txt")
    val o4 = run("stop", recs, Harness.RunOptions(maxCycles = 500, results = Some(outs)))
    assert(!o4.passed && o4.stopped && o4.verdict.startsWith("STOPPED at cycle 500 as asked (--max-cycles 500): "), o4.verdict)
    assert(o4.stats.exists(s => s.stopped && s.cycles == 500 && s.failure.isEmpty), o4.stats)
    // What came out before the stop was checked: a wrong colour in the first result out fails the stopped run.
    val firstOut = Files.readAllLines(outs).get(0).split(' ')(2).toInt
    val early = recs.indexWhere(_._1 == firstOut)
    val o5 = run("wrong-then-stop", recs.updated(early, recs(early).copy(_3 = recs(early)._3.updated(0, recs(early)._3(0) ^ 1))),
      Harness.RunOptions(maxCycles = 500))
    assert(!o5.passed && !o5.stopped && o5.verdict.contains(s"mismatch SO (q=$firstOut,"), o5.verdict)
  }

  test("harness: a read outside the node, photon and query arrays FAILs (the DRAM model checks every request's range)") {
    // Stubs that read query 7's record from the header, from the query stream (which only the
    // host reads) and from beyond the image.
    for (addr <- Seq(0L, image.streamBase, image.totalBytes + 1024)) {
      val o = run(s"stray$addr", stubRecords, Harness.RunOptions(seed = 9), stubExe(Some(addr)))
      assert(!o.passed && o.verdict == s"FAIL seed=9: memory protocol: a read of 32 bytes at 0x${addr.toHexString} is outside " +
        s"the node, photon and query arrays of the ${image.totalBytes}-byte image", o.verdict)
    }
  }
}
