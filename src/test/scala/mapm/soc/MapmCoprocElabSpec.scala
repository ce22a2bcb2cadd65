package mapm.soc

import mapm.params.MapmParams
import mapm.sim.Emit
import org.scalatest.funsuite.AnyFunSuite

/** The coprocessor elaborates and emits for the smallest MAPM, with its AXI4 and AXI4-Lite ports. */
class MapmCoprocElabSpec extends AnyFunSuite {
  test("MapmCoproc emits SystemVerilog with its AXI4 master, AXI4-Lite slave and interrupt") {
    val sv = Emit.systemVerilog(new MapmCoproc(MapmParams.small))
    for (port <- Seq("io_axi_ar_valid", "io_axi_aw_bits_len", "io_axi_w_bits_strb", "io_ctrl_aw_ready", "io_irq", "io_trace_0_bits_pixel"))
      assert(sv.contains(port), port)
  }
}
