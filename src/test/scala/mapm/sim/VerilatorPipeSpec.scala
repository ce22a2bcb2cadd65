package mapm.sim

import chisel3._
import chisel3.util._
import org.scalatest.funsuite.AnyFunSuite

/** A small pipeline with narrow, 64-bit and wide ports, checked against a reference computed
  * here: each output must equal the function of the inputs seen `latency` cycles earlier. */
class VerilatorPipeSpec extends AnyFunSuite {
  class Dut extends Module {
    override def desiredName = "PipeDut"
    val io = IO(new Bundle {
      val in = Flipped(Valid(new Bundle { val a = UInt(7.W); val b = UInt(64.W); val w = UInt(100.W) }))
      val out = Valid(new Bundle { val sum = UInt(8.W); val x = UInt(64.W); val w = UInt(100.W) })
    })
    val s1 = RegNext(io.in)
    io.out.valid := RegNext(s1.valid, false.B)
    io.out.bits.sum := RegNext(s1.bits.a +& 1.U)
    io.out.bits.x := RegNext(~s1.bits.b)
    io.out.bits.w := RegNext(s1.bits.w.rotateLeft(3))
  }

  test("streams random rows through an emitted design with 2 cycles of latency") {
    val dir = java.nio.file.Files.createTempDirectory("pipe")
    val pipe = VerilatorPipe.build(new Dut, Some(dir))
    val rnd = new scala.util.Random(3)
    val rows = IndexedSeq.fill(500)(Array(BigInt(1, rnd), BigInt(7, rnd), BigInt(64, rnd), BigInt(100, rnd)))
    val byName = pipe.inputs.map(_.name)
    assert(byName == Seq("io_in_valid", "io_in_bits_a", "io_in_bits_b", "io_in_bits_w"))
    val outs = pipe.runAll(rows)
    assert(outs.length == rows.length)
    val mask100 = (BigInt(1) << 100) - 1
    for (t <- 2 until rows.length) {
      val r = rows(t - 2); val o = outs(t)
      assert(o(pipe.out("io_out_valid")) == r(0))
      assert(o(pipe.out("io_out_bits_sum")) == r(1) + 1)
      assert(o(pipe.out("io_out_bits_x")) == (~r(2) & ((BigInt(1) << 64) - 1)))
      assert(o(pipe.out("io_out_bits_w")) == (((r(3) << 3) | (r(3) >> 97)) & mask100))
    }
    assert(outs(0)(pipe.out("io_out_valid")) == 0, "reset clears the valid bit")
  }

  test("a typed pipe takes the leaves of the chosen fields in field order and holds other inputs at 0") {
    val dir = java.nio.file.Files.createTempDirectory("pipe")
    val bits = VerilatorPipe.of(new Dut, Some(dir))(_.io.in.bits, _.io.out.bits)
    assert(bits.inputs.map(_.name) == Seq("io_in_bits_a", "io_in_bits_b", "io_in_bits_w"))
    assert(bits.outputs.map(_.name) == Seq("io_out_bits_sum", "io_out_bits_x", "io_out_bits_w"))
    val valid = VerilatorPipe.of(new Dut, Some(dir))(_.io.in, _.io.out.valid)
    assert(valid.inputs.map(_.name) == Seq("io_in_valid", "io_in_bits_a", "io_in_bits_b", "io_in_bits_w"))
    val rnd = new scala.util.Random(5)
    val rows = IndexedSeq.fill(100)(Array(BigInt(7, rnd), BigInt(64, rnd), BigInt(100, rnd)))
    val outs = bits.runAll(rows)
    for (t <- 2 until rows.length) assert(outs(t)(0) == rows(t - 2)(0) + 1 && outs(t)(1) == (~rows(t - 2)(1) & ((BigInt(1) << 64) - 1)))
    assert(valid.runAll(Seq.fill(5)(Array(BigInt(1), BigInt(0), BigInt(0), BigInt(0)))).map(_.toSeq) ==
      Seq(0, 0, 1, 1, 1).map(v => Seq(BigInt(v))), "valid follows its input two cycles later")
    val unbound = VerilatorPipe.of(new Dut, Some(dir))(_.io.in.bits, _.io.out).runAll(rows)
    assert(unbound.forall(o => o.length == 4 && o(0) == 0), "in.valid, outside the chosen field, stays 0")
    val outer = VerilatorPipe.of(new Outer, Some(dir))(_.io, _.io)
    assert(outer.inputs.map(_.name) == Seq("io_a_0", "io_a_1") && outer.outputs.map(_.name) == Seq("io_y_0", "io_y_1"))
  }

  class Inner extends Module {
    override def desiredName = "PipeInner"
    val io = IO(new Bundle { val a = Input(UInt(8.W)); val y = Output(UInt(8.W)) })
    io.y := RegNext(io.a * 3.U)
  }
  class Outer extends Module {
    override def desiredName = "PipeOuter"
    val io = IO(new Bundle { val a = Input(Vec(2, UInt(8.W))); val y = Output(Vec(2, UInt(8.W))) })
    for (i <- 0 until 2) { val u = Module(new Inner); u.io.a := io.a(i) + i.U; io.y(i) := u.io.y }
  }

  test("noInline keeps the named modules as their own C++ classes, with the same results") {
    val dir = java.nio.file.Files.createTempDirectory("pipe")
    val rnd = new scala.util.Random(4)
    val rows = IndexedSeq.fill(200)(Array(BigInt(8, rnd), BigInt(8, rnd)))
    for (keep <- Seq(Seq.empty, Seq("PipeInner"))) {
      val pipe = VerilatorPipe.build(new Outer, Some(dir), noInline = keep)
      val obj = pipe.exe.getParent.resolve("obj")
      assert(java.nio.file.Files.exists(obj.resolve("VPipeOuter_PipeInner.h")) == keep.nonEmpty, s"noInline = $keep")
      val outs = pipe.runAll(rows)
      for (t <- 1 until rows.length; i <- 0 until 2)
        assert(outs(t)(pipe.out(s"io_y_$i")) == ((rows(t - 1)(pipe.in(s"io_a_$i")) + i) * 3) % 256)
    }
  }
}
