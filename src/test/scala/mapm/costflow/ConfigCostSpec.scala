package mapm.costflow

import mapm.MapmError
import mapm.cost.Hierarchy
import org.scalatest.funsuite.AnyFunSuite

/** Which modules method (b) keeps whole: the same MAPM parts whether the MAPM is the top or sits
  * inside the coprocessor (a level lower), where keeping only two levels under the top had
  * flattened every TSM, SOM and SOA into its block. */
class ConfigCostSpec extends AnyFunSuite {
  private val mapm = Map(
    "Mapm_x" -> Seq("TsBlock", "SoBlock", "Uncore"),
    "TsBlock" -> Seq("Tsm", "Tsm", "TsL2"),
    "Tsm" -> Seq("Tsa", "ROCache_l1"),
    "Tsa" -> Seq("Stage"),
    "SoBlock" -> Seq("Som", "Som"),
    "Som" -> Seq("Soa", "Soa", "mem_8x4"),
    "Soa" -> Seq("Stage"),
    "Uncore" -> Seq("DataBus", "ROCache_l2"),
    "ROCache_l1" -> Seq("mem_8x4"), "ROCache_l2" -> Seq("mem_8x4"))
  private val mems = Map("mem_8x4" -> (4, 8))

  test("a bare MAPM keeps its blocks, their parts and every cache; not the units (unless named) or the arrays") {
    val kept = ConfigCost.keptModules(Hierarchy(mapm, mems), "Mapm_x", "Mapm_x")
    assert(kept.toSet == Set("TsBlock", "SoBlock", "Uncore", "Tsm", "TsL2", "Som", "DataBus", "ROCache_l1", "ROCache_l2"))
  }

  test("inside the coprocessor the same MAPM parts are kept, and the wrapper's modules and their parts too") {
    val coproc = mapm ++ Map("Coproc" -> Seq("Mapm_x", "Reader", "Acc", "mem_8x4"), "Acc" -> Seq("Combiner", "Fifo"),
      "Combiner" -> Seq("Switch"), "Fifo" -> Seq("mem_8x4"))
    val kept = ConfigCost.keptModules(Hierarchy(coproc, mems), "Coproc", "Mapm_x")
    val bare = ConfigCost.keptModules(Hierarchy(mapm, mems), "Mapm_x", "Mapm_x")
    assert(bare.forall(kept.contains), s"kept $kept")
    assert(kept.toSet -- bare == Set("Mapm_x", "Reader", "Acc", "Combiner", "Fifo"))
  }

  test("a unit named for its own power (the SOA) is kept too when the design has it; one it lacks is not invented") {
    val bare = ConfigCost.keptModules(Hierarchy(mapm, mems), "Mapm_x", "Mapm_x")
    val withSoa = ConfigCost.keptModules(Hierarchy(mapm, mems), "Mapm_x", "Mapm_x", Seq("Soa", "SOA_absent"))
    assert(withSoa.toSet -- bare == Set("Soa"))
  }

  test("a top that does not hold the MAPM is an error naming both") {
    val e = intercept[MapmError](ConfigCost.keptModules(Hierarchy(mapm, mems), "TsBlock", "Mapm_x"))
    assert(e.getMessage.contains("TsBlock") && e.getMessage.contains("Mapm_x"))
  }

  test("the boundary check names each registered part that has a path, and only those") {
    def m(name: String, registered: Boolean, paths: Int) = ujson.Obj("module" -> name, "registered" -> registered,
      "paths" -> paths, "examples" -> ujson.Arr.from((1 to paths).map(i => ujson.Str(s"io_a -> io_b$i (io_a -> io_b$i)"))))
    val j = ujson.Obj("methodB" -> ujson.Obj("boundaries" -> ujson.Obj("modules" ->
      ujson.Arr(m("Ring", registered = true, 0), m("Arbiter", registered = false, 5), m("Bus", registered = true, 2)))))
    assert(ConfigCost.boundaryViolations(j) ==
      Seq("Bus must have no combinational input-to-output path but has 2, e.g. io_a -> io_b1 (io_a -> io_b1)"))
  }
}
