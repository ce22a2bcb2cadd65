package mapm.shader

import mapm.Slow
import mapm.numerics.{Arith, CondModel, ConvChainModel, ConvVectorFiles, FloatFormat, ShaderVectors}
import mapm.sim.{PipeRunner, SoaRunner}
import mapm.sim.SoaRunner.{Op, Out}
import mapm.testutil.{Bubbles, ShaderCases, SharedFiles}
import org.scalatest.funsuite.AnyFunSuite

/** The conventional SOA (ConvShaderChain and the cond check) in Verilator: every row of the
  * conventional vector files (../shared/vectors/conventional, made with exact rationals) on all
  * three channels, then seeded random operations against the model with random valid gaps
  * (latency, order, no loss). */
@Slow
class ConvSoaHwSpec extends AnyFunSuite with SharedFiles {
  private val sims = scala.collection.mutable.Map.empty[FloatFormat, PipeRunner[Op, Out]]
  private def sim(f: FloatFormat): PipeRunner[Op, Out] = sims.getOrElseUpdate(f, SoaRunner(f, 3, arith = Arith.Conventional))

  private def collect(s: PipeRunner[Op, Out], cycles: Iterator[Option[Op]]): IndexedSeq[Out] = {
    val b = IndexedSeq.newBuilder[Out]
    s.run(cycles)(b += _)
    b.result()
  }

  for (v <- ConvVectorFiles.all) test(s"conventional/${v.file}: the hardware reproduces the result and flags of every row") {
    val rows = ShaderVectors.read(requireShared(s"vectors/conventional/${v.file}"), v.format)
    val ops = rows.zipWithIndex.map { case (r, k) =>
      Op(Array(r.kernel, r.brdf, r.h, r.power, r.power, r.power, r.contrib, r.contrib, r.contrib) ++ Array.fill(6)(0L), k)
    }
    val outs = collect(sim(v.format), ops.iterator.map(Some(_)))
    assert(outs.length == rows.length)
    for ((o, k) <- outs.zipWithIndex) {
      val r = rows(k)
      assert(o.tag == k, "results leave in order")
      for (c <- 0 until 3)
        assert(o.colour(c) == r.expected && o.flags(c) == r.flags,
          s"row id ${r.id} channel $c: hardware ${v.format.hex(o.colour(c))} flags ${o.flags(c)}, expected ${v.format.hex(r.expected)} flags ${r.flags}")
      assert(o.cond == CondModel.cond(v.format, 0L, 0L, 0L, 0L, 0L, 0L, r.h))
    }
  }

  for ((f, count) <- Seq((FloatFormat.fp32, 50000), (FloatFormat.fp16, 20000)))
    test(s"$f: $count random operations back to back, then with random valid gaps, equal the model") {
      val s = sim(f)
      val cases = new ShaderCases(f, seed = 77)
      val rnd = new scala.util.Random(78)
      val gapped = count / 5
      val ops = IndexedSeq.tabulate(count + gapped) { k =>
        val pos = Array.fill(6)(f.pack(0, f.bias + rnd.nextInt(3) - 1, rnd.nextLong() & f.manMask))
        Op(cases.operation() ++ pos, k & 0xffff)
      }
      val b = new Bubbles(ops, count, 0.4, 5)
      val inCycle = b.inCycle
      val outs = collect(s, b.stream)
      assert(outs.length == ops.length, "every operation leaves exactly once")
      for ((o, k) <- outs.zipWithIndex) {
        assert(o.tag == (k & 0xffff), s"tags leave in order: result $k carries tag ${o.tag}")
        assert(o.cycle - inCycle(k) == s.latency, s"operation $k: latency ${o.cycle - inCycle(k)}")
        val in = ops(k).inputs
        for (c <- 0 until 3) {
          val want = ConvChainModel.colour(f, in(0), in(1), in(2), in(3 + c), in(6 + c))
          assert(o.colour(c) == want.bits && o.flags(c) == want.flags,
            s"op $k channel $c (${in.map(f.hex).mkString(",")}): hardware ${f.hex(o.colour(c))}/${o.flags(c)}, model ${f.hex(want.bits)}/${want.flags}")
        }
        assert(o.cond == CondModel.cond(f, in(9), in(10), in(11), in(12), in(13), in(14), in(2)))
      }
    }
}
