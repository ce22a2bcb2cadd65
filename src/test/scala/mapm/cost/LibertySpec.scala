package mapm.cost

import java.nio.file.Files
import mapm.MapmError
import org.scalatest.funsuite.AnyFunSuite

/** The Liberty parser and Boolean functions: generic syntax on small texts, and the typed view of
  * the OSU 0.18 um library against numbers read off the file and hand-written truth tables.
  */
class LibertySpec extends AnyFunSuite {
  import BoolExpr._

  private def lib: Liberty.Library = YosysSynth.library

  private def parsed(s: String): BoolExpr = BoolExpr.parse(s).fold(msg => fail(msg), identity)

  test("Boolean functions: operators and precedence NOT > AND > XOR > OR") {
    val (a, b, c) = (Var("A"), Var("B"), Var("C"))
    assert(parsed("A + B C") == Or(a, And(b, c)))
    assert(parsed("A | B & C") == Or(a, And(b, c)))
    assert(parsed("A ^ B C") == Xor(a, And(b, c)))
    assert(parsed("A + B ^ C") == Or(a, Xor(b, c)))
    assert(parsed("A ^ B + C") == Or(Xor(a, b), c))
    assert(parsed("!A B") == And(Not(a), b))
    assert(parsed("A' * B") == And(Not(a), b))
    assert(parsed("(A+B)'") == Not(Or(a, b)))
    assert(parsed("!(A B)") == Not(And(a, b)))
    assert(parsed("A B C") == And(And(a, b), c))
    assert(parsed("A(B)") == And(a, b))
    assert(parsed("1 & A + 0") == Or(And(Const(true), a), Const(false)))
    assert(parsed("IQ'' ") == Not(Not(Var("IQ"))))
    assert(parsed("D[3] & x_y.z") == And(Var("D[3]"), Var("x_y.z")))
  }

  test("Boolean functions: syntax errors say where") {
    for (bad <- Seq("A +", "(A B", "A $ B", "", "A )", "3X")) {
      val err = BoolExpr.parse(bad)
      assert(err.isLeft, bad)
      assert(err.left.exists(_.contains("column")), err)
    }
  }

  test("generic syntax: groups, attributes, comments, continuations, missing semicolons") {
    val text =
      """/* header
        | comment */
        |library (demo) {
        |  time_unit : "100ps" ; // trailing comment
        |  capacitive_load_unit (1, ff);
        |  leakage_power_unit : 1uW
        |  cell (X) {
        |    area : 2.5;
        |    pin (A, B) { direction : input; capacitance : 0.5; }
        |    pin (Y) { direction : output; function : "A ^ \
        |B";
        |      timing () { related_pin : "A B";
        |        cell_rise (t) { index_1 ("1, 2"); values ("0.1, 0.2", \
        |                 "0.3, 0.4"); }
        |      }
        |    }
        |  }
        |}
        |""".stripMargin
    val g = LibertySyntax.parse(text, "demo.lib")
    assert(g.args == Seq("demo"))
    assert(g.simple("time_unit").map(_.value).contains("100ps"))
    assert(g.complex("capacitive_load_unit").map(_.args).contains(Seq("1", "ff")))
    assert(g.simple("leakage_power_unit").map(_.line).contains(6))
    assert(g.groups("cell").head.line == 7)
    val l = Liberty.parse(text, "demo.lib")
    assert(l.timeUnitNs == 0.1 && l.capUnitPf == 0.001 && l.leakageUnitNw == 1000.0)
    val x = l.cells("X")
    assert(x.area == 2.5 && x.inputs.map(_.name) == Seq("A", "B") && x.inputs.forall(_.capacitance == 0.5))
    val y = x.pin("Y").get
    assert(y.function.contains(Xor(Var("A"), Var("B"))))
    assert(y.timing.head.relatedPins == Seq("A", "B"))
    assert(y.timing.head.tables("cell_rise") == Liberty.Table(Seq(1, 2), Seq(), Seq(Seq(0.1, 0.2), Seq(0.3, 0.4))))
  }

  test("errors name the file and line") {
    def message(text: String): String = intercept[MapmError](Liberty.parse(text, "bad.lib")).getMessage
    assert(message("library (x) {\n  cell (A) {\n    area : 1;\n") == "bad.lib:3: missing '}' of group 'cell' opened on line 2")
    assert(message("library (x) {\n cell (A) {\n  area : big;\n }\n}") == "bad.lib:3: bad number 'big' for area of cell A")
    assert(message("library (x) {\n cell (A) {\n  pin (Y) { direction : output;\n function : \"A +\"; }\n }\n}")
      .startsWith("bad.lib:4: bad function of pin Y of cell A: unexpected end at column 4"))
    assert(message("library (x) {\n  = 3;\n}") == "bad.lib:2: expected ':' or '(' after '='")
    assert(message("library (x) {\n  : 3;\n}") == "bad.lib:2: expected a name, found ':'")
    assert(message("/* open") == "bad.lib:1: unterminated comment")
    assert(message("cell (A) { }") == "bad.lib: not a Liberty library (expected one 'library (name) { ... }' group)")
    val missing = Files.createTempDirectory("mapm-lib").resolve("none.lib")
    assert(intercept[MapmError](Liberty.read(missing)).getMessage == s"cannot read Liberty file $missing: no such file")
  }

  test("OSU 0.18 um: units, cell count, areas, capacitances, leakage (numbers read off the file)") {
    assert(lib.name == "osu018_stdcells")
    assert(lib.timeUnitNs == 1.0 && lib.capUnitPf == 1.0 && lib.leakageUnitNw == 1.0)
    assert(lib.cells.size == 32)
    assert(lib.cells("INVX1").area == 16)
    assert(lib.cells("NAND2X1").area == 24)
    assert(lib.cells("OAI21X1").area == 23)
    assert(lib.cells("DFFPOSX1").area == 96)
    assert(lib.cells("DFFSR").area == 176)
    assert(lib.cells("FAX1").area == 120)
    assert(lib.cells("LATCH").area == 0)
    assert(lib.cells("AND2X1").pin("A").get.capacitance == 0.0129077)
    assert(lib.cells("AND2X1").pin("B").get.capacitance == 0.0125298)
    assert(lib.cells("DFFPOSX1").pin("CLK").get.capacitance == 0.0279235)
    assert(lib.cells("INVX1").leakage == 0.0221741)
    assert(lib.cells("AND2X1").leakage == 0.0746794)
    assert(lib.cells("DFFPOSX1").pin("CLK").get.isClock)
    assert(lib.cells("FAX1").outputs.map(_.name) == Seq("YC", "YS"))
  }

  test("OSU 0.18 um: timing tables") {
    val arcs = lib.cells("AND2X1").pin("Y").get.timing
    assert(arcs.map(_.relatedPins) == Seq(Seq("A"), Seq("B")))
    val rise = arcs.head.tables("cell_rise")
    assert(rise.index1 == Seq(0.005, 0.0125, 0.025, 0.075, 0.15))
    assert(rise.index2 == Seq(0.06, 0.18, 0.42, 0.6, 1.2))
    assert(rise.values.size == 5 && rise.values.forall(_.size == 5))
    assert(rise.values(0)(0) == 0.06367 && rise.values(4)(4) == 0.325543)
    assert(arcs.head.tables.keySet == Set("cell_rise", "cell_fall", "rise_transition", "fall_transition"))
    // every combinational delay is below 5 ns, and positive at the fastest input slew (index_2 of
    // the two-index tables); some go slightly negative at slow slews into small loads (NAND3X1)
    for (c <- lib.cells.values; p <- c.outputs; t <- p.timing if t.timingType.isEmpty; k <- Seq("cell_rise", "cell_fall"); table <- t.tables.get(k)) {
      assert(table.max < 5 && table.min > -0.5, s"${c.name}/${p.name} $k")
      if (table.index2.nonEmpty) assert(table.index2.head == table.index2.min && table.values.forall(_.head > 0), s"${c.name}/${p.name} $k")
    }
    val q = lib.cells("DFFPOSX1").pin("Q").get.timing.head
    assert(q.relatedPins == Seq("CLK") && q.timingType.contains("rising_edge") && q.timingSense.contains("non_unate"))
    assert(q.tables("cell_rise").min > 0.05 && q.tables("cell_fall").max < 0.4) // clock to Q: 0.09 to 0.35 ns
  }

  test("OSU 0.18 um: flip-flops, latch, tristate") {
    val pos = lib.cells("DFFPOSX1").ff.get
    assert(pos.state == "DS0000" && pos.nextState == Var("D") && pos.clockedOn == Var("CLK") && pos.clear.isEmpty)
    assert(lib.cells("DFFPOSX1").pin("Q").get.function.contains(Var("DS0000")))
    assert(lib.cells("DFFNEGX1").ff.get.clockedOn == Not(Var("CLK")))
    val sr = lib.cells("DFFSR").ff.get
    assert(sr.clear.contains(Not(Var("R"))) && sr.preset.contains(Not(Var("S"))) && sr.clearPresetVar1.contains("L"))
    assert(lib.cells("DFFSR").isSequential && !lib.cells("NAND2X1").isSequential)
    val latch = lib.cells("LATCH")
    assert(latch.isSequential && latch.latch.get.enable.contains(Var("CLK")) && latch.latch.get.dataIn.contains(Var("D")))
    assert(lib.cells("TBUFX1").pin("Y").get.threeState.contains(Not(Var("EN"))))
  }

  test("OSU 0.18 um: every combinational cell's functions against hand-written truth tables, exhaustively") {
    val combinational = lib.cells.values.filter(c => !c.isSequential && c.pins.forall(_.threeState.isEmpty))
    assert(combinational.map(_.name).toSet == OsuTruth.inputs.keySet)
    for (cell <- combinational) {
      val inputs = cell.inputs.map(_.name)
      assert(inputs.toSet == OsuTruth.inputs(cell.name).toSet, cell.name)
      assert(cell.outputs.map(_.name) == OsuTruth.outputs(cell.name), cell.name)
      for (pin <- cell.outputs; bits <- 0 until (1 << inputs.size)) {
        val f = pin.function.get
        val env: OsuTruth.Env = name => ((bits >> inputs.indexOf(name)) & 1) == 1
        val where = inputs.zipWithIndex.map { case (n, i) => s"$n=${(bits >> i) & 1}" }.mkString(" ")
        assert(f.vars.subsetOf(inputs.toSet) && f.eval(env) == OsuTruth.functions((cell.name, pin.name))(env), s"${cell.name}/${pin.name} at $where")
      }
    }
  }
}
