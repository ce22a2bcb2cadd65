package mapm.shader

import mapm.fpu.{FAdd, FCmpLt, FMul, LintCheck, StreamCheck}
import mapm.fpu.FpuTesting.port
import mapm.model.{CondGen, CondModel, FloatFormat}
import mapm.sim.VerilatorPipe
import org.scalatest.funsuite.AnyFunSuite

/** CondCheck against CondModel (itself checked against exact rationals), streaming with random
  * idle cycles: every result exactly `latency` cycles after its input, with its tag, in order. */
class CondCheckSpec extends AnyFunSuite {
  private val names = Seq("qx", "qy", "qz", "px", "py", "pz", "h").map("io_in_bits_" + _)

  private def stream(f: FloatFormat, tagWidth: Int, count: Int, input: Int => Array[Long], seed: Long,
                     addCuts: Seq[Boolean] = FAdd.defaultCuts, mulCuts: Seq[Boolean] = FMul.defaultCuts,
                     cmpCuts: Seq[Boolean] = FCmpLt.defaultCuts): StreamCheck.Report = {
    val pipe = VerilatorPipe.build(new CondCheck(f, tagWidth, addCuts, mulCuts, cmpCuts))
    val (cond, tag) = (pipe.out("io_out_bits_cond"), pipe.out("io_out_bits_tag"))
    val tagMask = (1 << tagWidth) - 1
    StreamCheck.run(pipe, CondCheck.latency(addCuts, mulCuts, cmpCuts), count, names :+ "io_in_bits_tag",
      i => input(i).map(port) :+ BigInt(i & tagMask),
      (i, out) => {
        val in = input(i)
        val want = CondModel.cond(f, in(0), in(1), in(2), in(3), in(4), in(5), in(6))
        if (out(tag) != (i & tagMask)) s"tag ${out(tag)}, expected ${i & tagMask}"
        else if ((out(cond) == 1) != want) s"cond(${in.map(f.hex).mkString(", ")}) = ${out(cond)}, model $want"
        else null
      }, gap = 0.25, seed)
  }

  /** Case i of the e2m1 sweep: combination i * stride of the 16^7 input combinations. */
  private def e2m1Sweep(stride: Long)(i: Int): Array[Long] = {
    val f = FloatFormat(2, 1)
    val k = i.toLong * stride
    Array.tabulate(7)(j => (k >>> (f.width * j)) & f.mask)
  }

  test("latency: 16 cycles with the default cuts at fp32 and fp16 (instance value and formula agree)") {
    for (f <- Seq(FloatFormat.fp32, FloatFormat.fp16)) {
      var latency = -1
      circt.stage.ChiselStage.emitCHIRRTL { val m = new CondCheck(f, 4); latency = m.latency; m }
      assert(latency == 16 && CondCheck.latency() == 16, s"$f: instance $latency")
    }
    assert(CondCheck.latency(Seq(true, false, true, false), Seq(false, true, false), Seq(false)) == 7)
  }

  test("e2m1: every 1021st of all 16^7 input combinations (262,915 cases)") {
    val count = ((1L << 28) + 1020) / 1021
    val r = stream(FloatFormat(2, 1), 8, count.toInt, e2m1Sweep(1021), seed = 1)
    info(s"${r.operations} checks in ${r.cycles} cycles (${r.idleCycles} idle)")
  }

  test("fp32: 150,000 seeded cases (near the sphere, d2 == hh, zero distance, ties, specials); fp16: 50,000") {
    for ((f, count, seed) <- Seq((FloatFormat.fp32, 150000, 2L), (FloatFormat.fp16, 50000, 3L))) {
      val gen = new CondGen(f, seed)
      val cases = Array.fill(count)(gen.next())
      val r = stream(f, 16, count, cases, seed)
      info(s"$f: ${r.operations} checks in ${r.cycles} cycles (${r.idleCycles} idle)")
    }
  }

  test("with cuts left out (latency 7) it computes the same, e2m1 sweep") {
    stream(FloatFormat(2, 1), 3, 65000, e2m1Sweep(4129), seed = 4,
      Seq(true, false, true, false), Seq(false, true, false), Seq(false))
  }

  test("Verilator lint of the emitted SystemVerilog is clean (e2m1, fp16, fp32, fp64)") {
    for (f <- Seq(FloatFormat(2, 1), FloatFormat.fp16, FloatFormat.fp32, FloatFormat.fp64)) {
      val (top, messages) = LintCheck(new CondCheck(f, 12))
      assert(top == s"CondCheck_${f.name}_t12")
      assert(messages.isEmpty, s"$top:\n${messages.mkString("\n")}")
    }
  }
}
