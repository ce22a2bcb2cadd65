package mapm.cost

import chisel3._
import chisel3.util.Queue
import java.nio.charset.StandardCharsets
import java.nio.file.Files
import mapm.sim.Emit
import org.scalatest.funsuite.AnyFunSuite

/** Combinational input-to-output paths of mapped netlists: a hand-written netlist, and Chisel's
  * `Queue` in its four flavours, whose paths its documentation states (`pipe`: deq.ready to
  * enq.ready; `flow`: enq.valid to deq.valid, enq.bits to deq.bits). */
class CombPathsSpec extends AnyFunSuite {
  import YosysSynth.{library, tools}

  test("a hand-written netlist: through gates yes, through a flip-flop or a black box no") {
    tools()
    val json =
      """{"creator": "test", "modules": {"T": {"attributes": {"top": "00000000000000000000000000000001"},
        |  "ports": {
        |    "clock": {"direction": "input", "bits": [10]},
        |    "a": {"direction": "input", "bits": [11, 12]},
        |    "b": {"direction": "input", "bits": [13]},
        |    "c": {"direction": "input", "bits": [14]},
        |    "y": {"direction": "output", "bits": [20, 21, "0"]},
        |    "q": {"direction": "output", "bits": [30]},
        |    "m": {"direction": "output", "bits": [40]},
        |    "w": {"direction": "output", "bits": [14]}
        |  },
        |  "cells": {
        |    "u1": {"hide_name": 0, "type": "NAND2X1", "connections": {"A": [11], "B": [12], "Y": [20]}},
        |    "u2": {"hide_name": 0, "type": "INVX1", "connections": {"A": [20], "Y": [21]}},
        |    "r": {"hide_name": 0, "type": "DFFPOSX1", "connections": {"CLK": [10], "D": [13], "Q": [30]}},
        |    "mem": {"hide_name": 0, "type": "mem_4x1", "connections": {"R0_addr": [13], "R0_data": [40]}}
        |  },
        |  "netnames": {}}}}""".stripMargin
    val paths = CombPaths.of(Netlist.parse(json, "t.json"), library)
    assert(paths.map(p => (p.from, p.to)) == Seq("a" -> "y", "c" -> "w"), paths)
    assert(paths.head.example == "a[0] -> y[0]")
  }

  private def queuePaths(pipe: Boolean, flow: Boolean): Set[(String, String)] = {
    val dir = Files.createTempDirectory("mapm-combpaths")
    val top = s"Q_${pipe}_$flow"
    class Q extends Module {
      override def desiredName = top
      val io = IO(new Bundle {
        val enq = Flipped(chisel3.util.Decoupled(UInt(3.W)))
        val deq = chisel3.util.Decoupled(UInt(3.W))
      })
      io.deq <> Queue(io.enq, 2, pipe = pipe, flow = flow)
    }
    val sv = Emit.toFile(new Q, dir, s"$top.sv", forSynthesis = true)
    val r = YosysSynth(new String(Files.readAllBytes(sv), StandardCharsets.UTF_8), top)
    CombPaths.of(r.netlist, library).map(p => (p.from, p.to)).toSet
  }

  test("Chisel Queues: the paths their flavours promise, and no others") {
    tools()
    assert(queuePaths(pipe = false, flow = false) == Set.empty)
    assert(queuePaths(pipe = true, flow = false) == Set("io_deq_ready" -> "io_enq_ready"))
    assert(queuePaths(pipe = false, flow = true) == Set("io_enq_valid" -> "io_deq_valid", "io_enq_bits" -> "io_deq_bits"))
  }
}
