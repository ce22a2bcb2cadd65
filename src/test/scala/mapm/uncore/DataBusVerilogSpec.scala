package mapm.uncore

import java.security.MessageDigest
import mapm.fpu.LintCheck
import mapm.params.{MapmParams, SoBus}
import mapm.sim.Emit
import org.scalatest.funsuite.AnyFunSuite

/** The Data bus choices as Verilog: the dissertation's serial bus emits exactly what it emitted
  * before the ring bus was added (SHA-256 of its SystemVerilog recorded from the code before that
  * change, at 3/2/2 and 16/16/2), and the ring bus lints clean. */
class DataBusVerilogSpec extends AnyFunSuite {
  private def sha(gen: => chisel3.RawModule): String = {
    val v = circt.stage.ChiselStage.emitSystemVerilog(gen, Array.empty[String], Emit.firtoolOpts)
    MessageDigest.getInstance("SHA-256").digest(v.getBytes("UTF-8")).map("%02x".format(_)).mkString
  }

  for (((t, s, a), want) <- Seq((3, 2, 2) -> "d3e0e112599d1662f6e9901d8689793458a43a42f0ee9887521514b2578be30e", (16, 16, 2) -> "d36ffa7e77f38d516103fc8eef98d75e95cc0a9d3a48779694a9027562688140"))
    test(s"the serial Data bus at $t/$s/$a emits the Verilog it emitted before the ring bus") {
      assert(sha(new DataBus(MapmParams.table48(t, s, a))) == want)
    }

  for ((t, s, a) <- Seq((3, 2, 2), (16, 16, 2), (5, 3, 3)))
    test(s"the ring Data bus at $t/$s/$a lints clean (verilator -Wall)") {
      val p = MapmParams.table48(t, s, a)
      val (top, messages) = LintCheck(new RingBus(p.copy(uncore = p.uncore.copy(soBus = SoBus.Ring))))
      assert(top.startsWith("RingBus_"))
      assert(messages.isEmpty, messages.mkString("\n"))
    }
}
