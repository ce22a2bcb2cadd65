package mapm.cost

import mapm.MapmError
import org.scalatest.funsuite.AnyFunSuite

/** Reading yosys JSON netlists: a hand-written one in the shape `write_json` gives after
  * `splitnets -ports`, its nets, names, drivers and area; malformed ones.
  */
class NetlistSpec extends AnyFunSuite {
  private val json =
    """{"creator": "test", "modules": {
      |  "INVX1": {"attributes": {"blackbox": "00000000000000000000000000000001"}, "ports": {}, "cells": {}, "netnames": {}},
      |  "T": {"attributes": {"top": "00000000000000000000000000000001"},
      |    "ports": {
      |      "clock": {"direction": "input", "bits": [10]},
      |      "a[0]": {"direction": "input", "bits": [11]},
      |      "a[1]": {"direction": "input", "offset": 1, "bits": [12]},
      |      "y": {"direction": "output", "bits": [20, 21, "0", "1"]},
      |      "q": {"direction": "output", "bits": [30]}
      |    },
      |    "cells": {
      |      "u1": {"hide_name": 0, "type": "NAND2X1", "connections": {"A": [11], "B": [12], "Y": [20]}},
      |      "u2": {"hide_name": 0, "type": "INVX1", "connections": {"A": [20], "Y": [21]}},
      |      "r": {"hide_name": 0, "type": "DFFPOSX1", "connections": {"CLK": [10], "D": [21], "Q": [30]}},
      |      "$abc$1": {"hide_name": 1, "type": "BUFX2", "connections": {"A": ["x"], "Y": [40]}}
      |    },
      |    "netnames": {
      |      "n": {"hide_name": 0, "bits": [20, 21], "offset": 2},
      |      "$auto$3": {"hide_name": 1, "bits": [40]}
      |    }}}}""".stripMargin

  private val netlist = Netlist.parse(json, "t.json")

  test("ports (split ones grouped back), cells, dense nets, constants") {
    assert(netlist.top == "T")
    assert(netlist.ports.map(p => (p.name, p.width)) == Seq("clock" -> 1, "a" -> 2, "y" -> 4, "q" -> 1))
    val a = netlist.port("a").get
    assert(a.direction == Liberty.Direction.Input && a.nets == Seq(3, 4) && a.bitNames == Seq("a[0]", "a[1]"))
    assert(netlist.port("y").get.nets == Seq(5, 6, Netlist.Zero, Netlist.One))
    assert(netlist.port("y").get.bitNames == Seq("y[0]", "y[1]", "y[2]", "y[3]"))
    assert(netlist.netCount == 9)
    assert(netlist.cells.map(_.name) == Seq("u1", "u2", "r", "$abc$1"))
    assert(netlist.cells(0).pins == Map("A" -> 3, "B" -> 4, "Y" -> 5))
    assert(netlist.cells(3).pins == Map("A" -> Netlist.Zero, "Y" -> 8)) // "x" is 0
  }

  test("bit names: ports first, then visible wires, then hidden ones") {
    assert(netlist.bitNames(5) == Seq("y[0]", "n[2]"))
    assert(netlist.bitNames(6) == Seq("y[1]", "n[3]"))
    assert(netlist.bitNames(8) == Seq("$auto$3"))
    assert(netlist.names.find(_.name == "$auto$3").exists(_.hidden))
  }

  test("area and drivers against the library") {
    val lib = YosysSynth.library
    val area = netlist.area(lib)
    assert(area.total == 24 + 16 + 96 + 24 && area.sequential == 96 && area.combinational == 64)
    assert(area.counts == Map("NAND2X1" -> 1, "INVX1" -> 1, "DFFPOSX1" -> 1, "BUFX2" -> 1))
    val d = netlist.drivers(lib)
    assert(d(Netlist.Zero) == Netlist.Driver.Constant)
    assert(d(2) == Netlist.Driver.FromPort("clock"))
    assert(d(4) == Netlist.Driver.FromPort("a[1]"))
    assert(d(5) == Netlist.Driver.FromPin(0, "u1/Y"))
    assert(d(7) == Netlist.Driver.FromPin(2, "r/Q"))
    assert(d(8) == Netlist.Driver.FromPin(3, "$abc$1/Y"))
    val twice = netlist.copy(cells = netlist.cells :+ Netlist.Instance("u3", "INVX1", Map("A" -> 3, "Y" -> 6)))
    assert(intercept[MapmError](twice.drivers(lib)).getMessage == "net y[1] of module T has two drivers: pin u2/Y and pin u3/Y")
    val unknown = netlist.copy(cells = netlist.cells :+ Netlist.Instance("u4", "FOO", Map()))
    assert(intercept[MapmError](unknown.area(lib)).getMessage == "cell type FOO of instance u4 is not in library osu018_stdcells")
  }

  test("malformed netlists are one-line errors naming the file") {
    def message(text: String): String = intercept[MapmError](Netlist.parse(text, "bad.json")).getMessage
    assert(message("{").startsWith("bad.json: not JSON"))
    assert(message("""{"modules": 3}""") == "bad.json: not a yosys netlist: modules is not an object")
    assert(message("""{"modules": {"A": {"ports": {}}, "B": {"ports": {}}}}""") == "bad.json: 2 modules (A, B); name the top one")
    assert(Netlist.parse("""{"modules": {"A": {"ports": {}}, "B": {"ports": {}}}}""", "two.json", Some("B")).top == "B")
    assert(message(json.replace("\"B\": [12]", "\"B\": [12, 13]")) ==
      "bad.json: pin B of cell u1 (NAND2X1) connects 2 bits; expected a flat netlist of library cells")
    assert(message(json.replace("\"bits\": [30]", "\"bits\": [{}]")).startsWith("bad.json: not a yosys netlist: bad bit {} in q"))
  }

  test("a netlist read without its unused keys (YosysJson) gives the same ports and cells, no net names") {
    val file = java.nio.file.Files.createTempFile("mapm-yosysjson", ".json")
    java.nio.file.Files.write(file, json.replace("\"cells\": {", "\"parameters\": {\"X\": 1}, \"cells\": {").getBytes("UTF-8"))
    val j = YosysJson.read(file)
    val t = j("modules")("T")
    assert(t("attributes").isNull && t("netnames").isNull && t("parameters").isNull)
    assert(t("cells")("u1")("connections")("A").arr.map(_.num) == Seq(11.0))
    val n = Netlist.fromJson(j, "t.json", Some("T"))
    assert(n.ports == netlist.ports && n.cells == netlist.cells && n.names.isEmpty)
    assert(intercept[MapmError](YosysJson.read(file.resolveSibling("missing.json"))).getMessage.contains("not found"))
  }

  test("black boxes' multi-bit pins are read a bit a pin, only when asked") {
    val bb = json.replace("\"r\": {\"hide_name\": 0, \"type\": \"DFFPOSX1\", \"connections\": {\"CLK\": [10], \"D\": [21], \"Q\": [30]}}",
      "\"r\": {\"hide_name\": 0, \"type\": \"mem_2x2\", \"connections\": {\"A\": [11, 12], \"Q\": [30]}}")
    assert(intercept[MapmError](Netlist.parse(bb, "bb.json")).getMessage.contains("connects 2 bits"))
    val n = Netlist.fromJson(ujson.read(bb), "bb.json", Some("T"), Set("mem_2x2"))
    assert(n.cells.find(_.name == "r").get.pins == Map("A[0]" -> 3, "A[1]" -> 4, "Q" -> 7))
  }
}
