package mapm.shader

import mapm.Slow
import mapm.fpu.{FpuDepth, LintCheck, StreamCheck}
import mapm.fpu.FpuTesting.port
import mapm.numerics.{CondGen, CondModel, CondTables, FloatFormat}
import mapm.testutil.Sim
import org.scalatest.funsuite.AnyFunSuite

/** CondCheck against CondModel (itself checked against exact rationals), streaming with random
  * idle cycles: every result exactly `latency` cycles after its input, with its tag, in order. */
@Slow
class CondCheckSpec extends AnyFunSuite with Sim {
  /** `count` checks, input(i) = (qx, qy, qz, px, py, pz, h) tagged i, against CondModel: the
    * result must carry cond and the tag (fields cond, tag). */
  private def stream(f: FloatFormat, tagWidth: Int, count: Int, input: Int => Array[Long], seed: Long,
                     depth: Option[FpuDepth] = None): StreamCheck.Report = {
    val d = depth.getOrElse(FpuDepth.of(f))
    val tagMask = (1 << tagWidth) - 1
    StreamCheck.run(pipe(new CondCheck(f, tagWidth, d))(_.io.in, _.io.out), CondCheck.latency(d), count,
      i => input(i).toSeq.map(port) :+ BigInt(i & tagMask),
      i => {
        val in = input(i)
        Seq(if (CondModel.cond(f, in(0), in(1), in(2), in(3), in(4), in(5), in(6))) 1 else 0, i & tagMask)
      },
      i => s"cond(${input(i).map(f.hex).mkString(", ")}), tag ${i & tagMask}", gap = 0.25, seed)
  }

  /** Case i of the e2m1 sweep: combination i * stride of the 16^7 input combinations. */
  private def e2m1Sweep(stride: Long)(i: Int): Array[Long] = {
    val f = FloatFormat(2, 1)
    val k = i.toLong * stride
    Array.tabulate(7)(j => (k >>> (f.width * j)) & f.mask)
  }

  test("latency: three adders, a multiplier and a compare at the default depth (fp32 37, fp16 36)") {
    for ((f, want) <- Seq(FloatFormat.fp32 -> 37, FloatFormat.fp16 -> 36)) {
      var latency = -1
      circt.stage.ChiselStage.emitCHIRRTL { val m = new CondCheck(f, 4); latency = m.latency; m }
      assert(latency == want && CondCheck.latency(FpuDepth.of(f)) == want, s"$f: instance $latency")
    }
    assert(CondCheck.latency(FpuDepth(2, 0, 0, 0)) == 6)
  }

  /** The inputs of a tiny format `f` whose operand h has sign bit `hSign` (half of all 2^(7·w))
    * through a [[CondCheckBench]] of 2^laneBits lanes, against the exact reference's operation
    * tables, with idle cycles (random data, valid low) before a fraction `gap` of the cycles:
    * each lane's cond must equal the reference and out.valid must be set in every lane exactly
    * `latency` cycles after each valid cycle and in no other cycle. Returns (cases, cond true,
    * cycles). */
  private def exhaustive(f: FloatFormat, hSign: Int, laneBits: Int, gap: Double, seed: Long): (Long, Long, Long) = {
    val t = new CondTables(f)
    // rows (valid, hi), outputs (cond, allValid, anyValid)
    val pipe = this.pipe(new CondCheckBench(f, laneBits), noInline = Seq("CondCheck_"))(_.io, _.io)
    val latency = CondCheck.latency(FpuDepth.of(f))
    val lanes = 1 << laneBits
    val lines = 1 << (7 * f.width - laneBits - 1) // h's sign is the top bit of the case index
    val first = hSign * lines
    val rnd = new scala.util.Random(seed)
    val schedule = { // the input word of each cycle, or -1 for an idle cycle
      val b = Array.newBuilder[Int]
      for (l <- first until first + lines) {
        if (rnd.nextDouble() < gap) for (_ <- 0 to rnd.nextInt(3)) b += -1
        b += l
      }
      for (_ <- 0 until latency + 2) b += -1
      b.result()
    }
    val (vIn, hiIn) = (0, 1)
    val (condOut, allV, anyV) = (0, 1, 2)
    val garbage = new scala.util.Random(seed + 1) // used by the writer thread only
    val hiBits = 7 * f.width - laneBits
    val rows = schedule.iterator.map { l =>
      val row = new Array[BigInt](2)
      row(vIn) = BigInt(if (l >= 0) 1 else 0)
      row(hiIn) = if (l >= 0) BigInt(l) else BigInt(hiBits, garbage)
      row
    }
    val s = t.size
    def op(k: Long, j: Int) = CondTables.operand(f, k, j)
    var errors = List.empty[String]; var errorCount = 0L
    def error(msg: => String): Unit = { errorCount += 1; if (errorCount <= 10) errors ::= msg }
    var cases = 0L; var trues = 0L; var cycle = 0
    val want = new Array[Long]((lanes + 63) / 64)
    val cycles = pipe.run(rows) { out =>
      val l = if (cycle >= latency) schedule(cycle - latency) else -1
      val (all, any) = (out(allV) == 1, out(anyV) == 1)
      if (all != any || all != (l >= 0)) error(s"cycle $cycle: out.valid all $all, any $any, expected ${l >= 0}")
      else if (l >= 0) {
        java.util.Arrays.fill(want, 0L)
        for (lane <- 0 until lanes) {
          val k = l.toLong * lanes + lane
          def d(i: Int) = t.sub(op(k, i) * s + op(k, i + 3))
          val (dx, dy, dz, h) = (d(0), d(1), d(2), op(k, 6))
          val d2 = t.add(t.add(t.mul(dx * s + dx) * s + t.mul(dy * s + dy)) * s + t.mul(dz * s + dz))
          if (t.lt(d2 * s + t.mul(h * s + h))) { want(lane >> 6) |= 1L << (lane & 63); trues += 1 }
        }
        val got = out(condOut)
        for (i <- want.indices) {
          val g = (got >> (64 * i)).toLong & (if (lanes - 64 * i >= 64) -1L else (1L << (lanes - 64 * i)) - 1)
          if (g != want(i)) {
            val lane = 64 * i + java.lang.Long.numberOfTrailingZeros(g ^ want(i))
            val k = l.toLong * lanes + lane
            error(s"cond(${(0 until 7).map(j => f.hex(op(k, j).toLong)).mkString(", ")}) = ${(g >>> (lane & 63)) & 1}, reference ${(want(i) >>> (lane & 63)) & 1}")
          }
        }
        cases += lanes
      }
      cycle += 1
    }
    assert(errorCount == 0, s"${pipe.top}: $errorCount errors (cycles with a wrong valid or a wrong cond in some lane), first ones:\n" + errors.reverse.mkString("\n"))
    assert(cycles == schedule.length && cases == (1L << (7 * f.width - 1)), s"${pipe.top}: $cycles cycles, $cases cases")
    (cases, trues, cycles)
  }

  // All 16^7 = 268,435,456 e2m1 inputs, in two tests of 134,217,728 (about a minute each).
  for (hSign <- 0 to 1) test(s"e2m1: all 16^6 · 8 = 134,217,728 input combinations with h ${if (hSign == 0) "0x0 … 0x7 (sign 0)" else "0x8 … 0xf (sign 1)"}, specials included, against the exact reference") {
    val t0 = System.nanoTime
    val (cases, trues, cycles) = exhaustive(FloatFormat(2, 1), hSign, laneBits = 6, gap = 0.05, seed = 1 + hSign)
    info(f"$cases cases ($trues with cond true) in $cycles cycles of 64 lanes, ${(System.nanoTime - t0) / 1e9}%.1f s")
    assert(trues > 0 && trues < cases)
  }

  test("fp32: 150,000 seeded cases (near the sphere, d2 == hh, zero distance, ties, specials); fp16: 50,000") {
    for ((f, count, seed) <- Seq((FloatFormat.fp32, 150000, 2L), (FloatFormat.fp16, 50000, 3L))) {
      val gen = new CondGen(f, seed)
      val cases = Array.fill(count)(gen.next())
      val r = stream(f, 16, count, cases, seed)
      info(s"$f: ${r.operations} checks in ${r.cycles} cycles (${r.idleCycles} idle)")
    }
  }

  test("at other depths (latency 7 and 0) it computes the same, e2m1 sweep") {
    for (d <- Seq(FpuDepth(2, 1, 0, 0), FpuDepth(0, 0, 0, 0)))
      stream(FloatFormat(2, 1), 3, 65000, e2m1Sweep(4129), seed = 4, Some(d))
  }

  test("Verilator lint of the emitted SystemVerilog is clean (e2m1, fp16, fp32, fp64)") {
    for (f <- Seq(FloatFormat(2, 1), FloatFormat.fp16, FloatFormat.fp32, FloatFormat.fp64)) {
      val (top, messages) = LintCheck(new CondCheck(f, 12))
      val d = FpuDepth.of(f)
      assert(top == s"CondCheck_${f.name}_t12_a${d.add}m${d.mul}c1")
      assert(messages.isEmpty, s"$top:\n${messages.mkString("\n")}")
    }
  }
}
