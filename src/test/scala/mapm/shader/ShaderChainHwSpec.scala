package mapm.shader

import mapm.Slow
import mapm.numerics.{FloatFormat, ShaderChainModel, ShaderVectorFiles, ShaderVectors}
import mapm.testutil.{Bubbles, ShaderCases, SharedFiles}
import org.scalatest.funsuite.AnyFunSuite
import mapm.sim.{PipeRunner, ShaderChainRunner}
import mapm.sim.ShaderChainRunner.{Op, Out}

/** The emitted ShaderChain in Verilator against the vector files (result and flags of every
  * row) and against the bit-accurate model on seeded random operations streamed back to back
  * in one simulation, then with random valid gaps (latency, order, no loss). */
@Slow
class ShaderChainHwSpec extends AnyFunSuite with SharedFiles {
  private val sims = scala.collection.mutable.Map.empty[(FloatFormat, Int), PipeRunner[Op, Out]]
  private def sim(f: FloatFormat, g: Int): PipeRunner[Op, Out] = sims.getOrElseUpdate((f, g), ShaderChainRunner(f, g))

  for (v <- ShaderVectorFiles.all) test(s"${v.file}: the hardware reproduces the result and flags of every row") {
    val rows = ShaderVectors.read(requireShared(s"vectors/${v.file}"), v.format)
    // Row k drives all three channels (so each channel is checked on every row).
    val ops = rows.zipWithIndex.map { case (r, k) =>
      Op(Array(r.kernel, r.brdf, r.h, r.power, r.power, r.power, r.contrib, r.contrib, r.contrib), k)
    }
    val outs = collect(sim(v.format, v.g), ops.iterator.map(Some(_)))
    assert(outs.length == rows.length)
    for ((o, k) <- outs.zipWithIndex) {
      val r = rows(o.tag.toInt)
      assert(o.tag == k, "results leave in order")
      for (c <- 0 until 3)
        assert(o.colour(c) == r.expected && o.flags(c) == r.flags,
          s"row id ${r.id} channel $c: hardware ${v.format.hex(o.colour(c))} flags ${o.flags(c)}, expected ${v.format.hex(r.expected)} flags ${r.flags}")
    }
  }

  private val configs = Seq((FloatFormat.fp32, 100000), (FloatFormat.fp16, 30000))
  for ((f, count) <- configs; g <- Seq(0, 2, 3))
    test(s"$f, g = $g: $count random operations back to back, then with random valid gaps, equal the model") {
      val s = sim(f, g)
      val model = new ShaderChainModel(f, g)
      val cases = new ShaderCases(f, seed = 1000 + g)
      val gapped = count / 5
      val ops = IndexedSeq.tabulate(count + gapped)(k => Op(cases.operation(), k & 0xffff)) // 16-bit tags wrap
      // Back to back first, then a bubble before an operation with probability 0.4 (runs of them).
      val b = new Bubbles(ops, count, 0.4, g)
      val inCycle = b.inCycle
      val outs = collect(s, b.stream)
      assert(outs.length == ops.length, "every operation leaves exactly once")
      for ((o, k) <- outs.zipWithIndex) {
        assert(o.tag == (k & 0xffff), s"tags leave in order: result $k carries tag ${o.tag}")
        assert(o.cycle - inCycle(k) == s.latency, s"operation $k: latency ${o.cycle - inCycle(k)}")
        val in = ops(k).inputs
        val front = model.front(in(0), in(1), in(2))
        for (c <- 0 until 3) {
          val want = model.channel(front, in(3 + c), in(6 + c))
          assert(o.colour(c) == want.bits && o.flags(c) == want.flags,
            s"op $k channel $c (${in.map(f.hex).mkString(",")}): hardware ${f.hex(o.colour(c))}/${o.flags(c)}, model ${f.hex(want.bits)}/${want.flags}")
        }
      }
    }

  private def collect(s: PipeRunner[Op, Out], cycles: Iterator[Option[Op]]): IndexedSeq[Out] = {
    val b = IndexedSeq.newBuilder[Out]
    s.run(cycles)(b += _)
    b.result()
  }
}
