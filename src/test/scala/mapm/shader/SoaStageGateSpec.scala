package mapm.shader

import mapm.Slow
import mapm.numerics.{Arith, FloatFormat}
import mapm.sim.Emit
import mapm.testutil.Sim
import org.scalatest.funsuite.AnyFunSuite
import scala.collection.mutable.ArrayBuffer

/** Stage clock gating (mapm.util.StageGates) inside the SOA, online and conventional: the gated
  * SOA against the same SOA with every register clocked in every cycle, both in Verilator on one
  * row stream: seeded random operations with runs of idle cycles whose data inputs carry random
  * garbage (what a gated register must not take), then a long idle stretch and a burst. Every
  * valid result beat (its cycle and every output field) must be the same, and the valid bit the
  * same in every cycle. The gated SOA has a clock gate per pipeline depth; the ungated none. */
@Slow
class SoaStageGateSpec extends AnyFunSuite with Sim {
  private def rows(widths: Seq[Int], count: Int, seed: Long): IndexedSeq[Array[BigInt]] = {
    val rnd = new scala.util.Random(seed)
    val out = ArrayBuffer.empty[Array[BigInt]]
    def row(valid: Boolean) = Array.tabulate(widths.length)(k => if (k == 0) BigInt(if (valid) 1 else 0) else BigInt(widths(k), rnd))
    for (i <- 0 until count) {
      if (rnd.nextDouble() < 0.5) for (_ <- 0 to rnd.nextInt(4)) out += row(false)
      if (i == count / 2) for (_ <- 0 until 100) out += row(false) // longer than the pipeline
      out += row(true)
    }
    for (_ <- 0 until 120) out += row(false)
    out.toIndexedSeq
  }

  for ((f, g, arith) <- Seq((FloatFormat.fp16, 3, Arith.Online), (FloatFormat.fp16, 3, Arith.Conventional)))
    test(s"$f g = $g $arith SOA: stage-gated and ungated give the same result beats in the same cycles") {
      val gated = pipe(new SOA(f, g, 8, arith = arith))(_.io.in, _.io.out)
      val ungated = pipe(new SOA(f, g, 8, arith = arith, stageGate = false))(_.io.in, _.io.out)
      assert(gated.top == SOA.name(f, g, arith = arith) && ungated.top == gated.top + "_nsg")
      val in = rows(gated.inputs.map(_.width), 3000, seed = 77)
      def run(p: mapm.sim.VerilatorPipe): IndexedSeq[IndexedSeq[BigInt]] = p.runAll(in).map(_.toIndexedSeq)
      val (a, b) = (run(gated), run(ungated))
      assert(a.length == b.length)
      val validA = a.indices.filter(a(_)(0) == 1)
      assert(validA == b.indices.filter(b(_)(0) == 1), "valid in the same cycles")
      assert(validA.size == 3000, "every operation leaves once")
      for (c <- validA.find(c => a(c) != b(c)))
        fail(s"cycle $c: gated ${a(c).map(_.toString(16))}, ungated ${b(c).map(_.toString(16))}")
      val gates = Seq(true, false).map(sg => Emit.systemVerilog(new SOA(f, g, 8, arith = arith, stageGate = sg))
        .linesIterator.count(_.trim.startsWith("ClockGate ")))
      assert(gates(0) >= SOA.latency(f, g, mapm.fpu.FpuDepth.of(f), arith) && gates(1) == 0, s"clock gate instances: $gates")
      info(s"${validA.size} results in ${a.length} cycles, identical; ${gates(0)} stage clock gates")
    }
}
