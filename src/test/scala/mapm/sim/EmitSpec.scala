package mapm.sim

import chisel3._
import mapm.sim.SvStats
import mapm.util.ClockGate
import org.scalatest.funsuite.AnyFunSuite

/** A register of 8 bits behind a clock gate, and one of 3 bits on the free-running clock. */
class GatedPair extends Module {
  val io = IO(new Bundle {
    val en = Input(Bool())
    val d = Input(UInt(8.W))
    val q = Output(UInt(8.W))
    val n = Output(UInt(3.W))
  })
  io.q := withClock(ClockGate(clock, io.en)) { RegNext(io.d, 0.U) }
  val count = RegInit(0.U(3.W))
  count := count + 1.U
  io.n := count
}

/** [[Emit]]: black boxes with inline Verilog written out with the design, and firtool's failures
  * as one line. */
class EmitSpec extends AnyFunSuite {
  test("a design with a ClockGate: its module once, no black-box file list, the latch not counted as a flip-flop") {
    val sv = Emit.systemVerilog(new GatedPair)
    assert("""(?m)^module ClockGate\(""".r.findAllMatchIn(sv).size == 1, sv)
    assert(sv.contains("always_latch") && !sv.contains("firrtl_black_box_resource_files") && !sv.trim.endsWith(".sv"))
    assert(SvStats.modules(sv).toSet == Set("GatedPair", "ClockGate"))
    assert(SvStats.registerBits(sv, "GatedPair") == 8 + 3)
    assert(SvStats.registerBits(sv, "ClockGate") == 0)
  }

  test("firtool killed (exit 137) or failing with a message: one line naming the code and the reason") {
    // The message of Chisel 6.7's FirtoolNonZeroExitCode, as `emit --tsm 256 --som 256 --soa 4` got it.
    val killed = "/root/.cache/llvm-firtool/1.62.1/bin/firtool returned a non-zero exit code. Note that this version of Chisel " +
      "(6.7.0) was published against firtool version 1.62.1.\n" + "-" * 78 + "\nExitCode:\n137\nSTDOUT:\n\nSTDERR:\n\n" + "-" * 78
    val k = Emit.firtoolFailure(killed)
    assert(!k.contains("\n") && k.contains("exit code 137") && k.contains("out of memory"), k)
    val failed = killed.replace("137", "1").replace("STDERR:\n\n", "STDERR:\nerror: something broke\nmore\n")
    val f = Emit.firtoolFailure(failed)
    assert(f == "firtool failed with exit code 1: error: something broke", f)
  }
}
