package mapm.shader

import mapm.Slow
import mapm.fpu.{FpuDepth, LintCheck}
import mapm.numerics.{CondGen, CondModel, FloatFormat, ShaderChainModel}
import mapm.testutil.{Bubbles, ShaderCases}
import org.scalatest.funsuite.AnyFunSuite
import mapm.sim.SoaRunner
import mapm.sim.SoaRunner.{Op, Out}

/** The SOA top (colour chain and cond check side by side) in Verilator against the bit-accurate
  * models ShaderChainModel (colour, flags) and CondModel (cond): seeded random operations back to
  * back in one simulation, then with random valid gaps; every result exactly `latency` cycles
  * after its operation, with its tag, in order, none lost; and Verilator lint. */
@Slow
class SOASpec extends AnyFunSuite {
  test("latency and name: fp32's colour chain is the longer path (42 at g = 0, 45 at g = 3), fp16's cond check (36)") {
    for ((f, g, chain, cond) <- Seq((FloatFormat.fp32, 0, 42, 37), (FloatFormat.fp32, 3, 45, 37), (FloatFormat.fp16, 3, 32, 36))) {
      assert(ShaderChain.latency(f, g) == chain && CondCheck.latency(FpuDepth.of(f)) == cond, s"$f g = $g")
      assert(SOA.latency(f, g) == math.max(chain, cond), s"$f g = $g")
      assert(SOA.name(f, g) == s"SOA_${f.name}_g$g" && SOA.name(f, g, Some(FpuDepth.of(f))) == s"SOA_${f.name}_g$g")
    }
    assert(SOA.name(FloatFormat.fp32, 3, Some(FpuDepth(4, 3, 1, 0))) == "SOA_e8m23_g3_a4m3c1")
    var instance = -1
    circt.stage.ChiselStage.emitCHIRRTL { val m = new SOA(FloatFormat(5, 4), 0, 8); instance = m.latency; m }
    assert(instance == 34 && SOA.latency(FloatFormat(5, 4), 0) == 34, s"e5m4 g = 0: instance $instance")
    circt.stage.ChiselStage.emitCHIRRTL { val m = new SOA(FloatFormat(5, 4), 0, 8, Some(FpuDepth(4, 3, 1, 0))); instance = m.latency; m }
    assert(instance == 23, s"e5m4 g = 0 with a 16-cycle cond check: instance $instance")
  }

  /** Seeded operations: colour inputs from ShaderCases; positions (and, 70 % of the time, h) from
    * CondGen (near the sphere, d2 == hh exactly, zero distance, rounding ties, extremes, specials);
    * otherwise h from ShaderCases with CondGen's positions. */
  private def operations(f: FloatFormat, count: Int, seed: Long): IndexedSeq[Op] = {
    val colour = new ShaderCases(f, seed)
    val cond = new CondGen(f, seed + 1)
    val rnd = new scala.util.Random(seed + 2)
    IndexedSeq.tabulate(count) { k =>
      val c = colour.operation()
      val d = cond.next()
      if (rnd.nextDouble() < 0.7) c(2) = d(6)
      Op(c ++ d.take(6), k & 0xffff)
    }
  }

  private def streamCheck(f: FloatFormat, g: Int, count: Int, gapped: Int, seed: Long): Unit = {
    val sim = SoaRunner(f, g)
    val chain = new ShaderChainModel(f, g)
    val ops = operations(f, count + gapped, seed)
    // Back to back first, then a bubble before an operation with probability 0.4 (runs of them).
    val b = new Bubbles(ops, count, 0.4, seed)
    val inCycle = b.inCycle
    val outs = IndexedSeq.newBuilder[Out]
    sim.run(b.stream)(outs += _)
    val res = outs.result()
    assert(res.length == ops.length, "every operation leaves exactly once")
    var passing = 0; var flagged = 0
    for ((o, k) <- res.zipWithIndex) {
      val in = ops(k).inputs
      assert(o.tag == (k & 0xffff), s"tags leave in order: result $k carries tag ${o.tag}")
      assert(o.cycle - inCycle(k) == sim.latency, s"operation $k: latency ${o.cycle - inCycle(k)}")
      val wantCond = CondModel.cond(f, in(9), in(10), in(11), in(12), in(13), in(14), in(2))
      assert(o.cond == wantCond, s"op $k cond(${in.drop(9).map(f.hex).mkString(",")}, h ${f.hex(in(2))}): hardware ${o.cond}")
      if (o.cond) passing += 1
      val front = chain.front(in(0), in(1), in(2))
      for (c <- 0 until 3) {
        val want = chain.channel(front, in(3 + c), in(6 + c))
        if (want.flags != 0) flagged += 1
        assert(o.colour(c) == want.bits && o.flags(c) == want.flags,
          s"op $k channel $c (${in.take(9).map(f.hex).mkString(",")}): hardware ${f.hex(o.colour(c))}/${o.flags(c)}, " +
            s"model ${f.hex(want.bits)}/${want.flags}")
      }
    }
    info(s"$f g = $g: ${ops.length} operations ($count back to back, $gapped with gaps), cond true in $passing, " +
      s"$flagged flagged channels")
    assert(passing > ops.length / 10 && passing < ops.length * 9 / 10, "both cond outcomes are exercised")
  }

  test("fp32, g = 3: 20,000 random operations back to back, then 5,000 with random valid gaps, equal the models") {
    streamCheck(FloatFormat.fp32, 3, 20000, 5000, seed = 31)
  }

  test("fp16, g = 3: 20,000 random operations back to back, then 5,000 with random valid gaps, equal the models") {
    streamCheck(FloatFormat.fp16, 3, 20000, 5000, seed = 16)
  }

  test("Verilator lint (-Wall, one file per module) is clean: fp32 g = 0 and 3, fp16 g = 3") {
    for ((f, g) <- Seq(FloatFormat.fp32 -> 0, FloatFormat.fp32 -> 3, FloatFormat.fp16 -> 3)) {
      val (top, messages) = LintCheck(new SOA(f, g))
      assert(top == SOA.name(f, g))
      assert(messages.isEmpty, s"$top:\n${messages.mkString("\n")}")
    }
  }
}
