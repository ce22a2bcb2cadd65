package mapm.cost

import java.nio.charset.StandardCharsets
import java.nio.file.{Files, Path}
import mapm.MapmError
import LibertySyntax.{ComplexAttribute, Group, SimpleAttribute}

/** Liberty (.lib) cell libraries.
  *
  * Two layers. [[LibertySyntax.parse]] reads any Liberty text into a tree of groups, simple and
  * complex attributes. [[Liberty.read]] and [[Liberty.parse]] then give the typed view a gate-level
  * flow needs: units, and per cell its area, leakage, pins (direction, capacitance, function,
  * timing tables) and its `ff`/`latch` group.
  *
  * Not read: `bus` and `bundle` pins, `statetable`, `ff_bank`/`latch_bank`, per-state
  * `leakage_power` groups, power tables and operating conditions.
  */
object Liberty {
  /** The direction of a cell pin (or of a netlist port). */
  sealed trait Direction

  /** The cases of [[Direction]]. */
  object Direction {
    case object Input extends Direction
    case object Output extends Direction
    case object Inout extends Direction
    case object Internal extends Direction
  }

  /** A library. The units are scale factors: one library time unit is `timeUnitNs` ns, one
    * capacitance unit `capUnitPf` pF, one leakage power unit `leakageUnitNw` nW. A unit the file
    * does not give is taken as 1 ns, 1 pF, 1 nW.
    */
  final case class Library(name: String, timeUnitNs: Double, capUnitPf: Double, leakageUnitNw: Double, cells: Map[String, Cell])

  /** A cell. `area` is in the library's area unit (um^2 for the usual libraries), `leakage` its
    * `cell_leakage_power` (0 when absent) in library leakage units.
    */
  final case class Cell(name: String, area: Double, leakage: Double, pins: Seq[Pin], ff: Option[Ff], latch: Option[Latch]) {
    /** Whether it holds state (an `ff` or a `latch` group). */
    def isSequential: Boolean = ff.isDefined || latch.isDefined

    /** The pin called `pinName`. */
    def pin(pinName: String): Option[Pin] = pins.find(_.name == pinName)

    /** The input pins, in file order. */
    def inputs: Seq[Pin] = pins.filter(_.direction == Direction.Input)

    /** The output pins, in file order. */
    def outputs: Seq[Pin] = pins.filter(_.direction == Direction.Output)
  }

  /** A pin. `capacitance` is in library capacitance units (0 when absent); `function` and
    * `threeState` are its `function` and `three_state` strings; `isClock` its `clock : true`.
    */
  final case class Pin(
      name: String,
      direction: Direction,
      capacitance: Double,
      function: Option[BoolExpr],
      threeState: Option[BoolExpr],
      isClock: Boolean,
      timing: Seq[Timing])

  /** A `timing()` group of a pin: the arcs from `relatedPins` to this pin. `tables` holds each
    * sub-group that has `values` (`cell_rise`, `cell_fall`, `rise_transition`, `fall_transition`,
    * `rise_constraint` ...) by its group name.
    */
  final case class Timing(relatedPins: Seq[String], timingType: Option[String], timingSense: Option[String], tables: Map[String, Table])

  /** A lookup table: `values(i)(j)` at `index1(i)`, `index2(j)` (one row when it has one index).
    * Values are in library units (time tables: `timeUnitNs` ns).
    */
  final case class Table(index1: Seq[Double], index2: Seq[Double], values: Seq[Seq[Double]]) {
    /** The smallest value. */
    def min: Double = values.flatten.min

    /** The largest value. */
    def max: Double = values.flatten.max
  }

  /** An `ff (state, stateInverted) { ... }` group: a flip-flop that loads `nextState` on the
    * rising edge of `clockedOn`; `clear`/`preset` force the state to 0/1; when both are active the
    * state is `clearPresetVar1` and the inverted state `clearPresetVar2` (each `L`, `H`, `N`, `T`
    * or `X` as the file writes it).
    */
  final case class Ff(
      state: String,
      stateInverted: String,
      nextState: BoolExpr,
      clockedOn: BoolExpr,
      clear: Option[BoolExpr],
      preset: Option[BoolExpr],
      clearPresetVar1: Option[String],
      clearPresetVar2: Option[String])

  /** A `latch (state, stateInverted) { ... }` group: transparent while `enable` is 1. */
  final case class Latch(
      state: String,
      stateInverted: String,
      dataIn: Option[BoolExpr],
      enable: Option[BoolExpr],
      clear: Option[BoolExpr],
      preset: Option[BoolExpr])

  /** Reads the library in `path`; a [[MapmError]] naming the file (and line) when it cannot. */
  def read(path: Path): Library = {
    if (!Files.isRegularFile(path)) MapmError.fail(s"cannot read Liberty file $path: no such file")
    val text =
      try new String(Files.readAllBytes(path), StandardCharsets.ISO_8859_1)
      catch { case e: java.io.IOException => MapmError.fail(s"cannot read Liberty file $path: ${e.getMessage}") }
    parse(text, path.toString)
  }

  /** The typed view of Liberty `text`; `source` names it in error messages. */
  def parse(text: String, source: String): Library = new TypedView(source).library(LibertySyntax.parse(text, source))

  /** Builds the typed view from the syntax tree, with errors naming `source` and the line. */
  private final class TypedView(source: String) {
    private def fail(line: Int, what: String): Nothing = MapmError.fail(s"$source:$line: $what")

    private def number(text: String, line: Int, what: String): Double =
      text.trim.toDoubleOption.getOrElse(fail(line, s"bad number '$text' for $what"))

    private def numbers(args: Seq[String], line: Int, what: String): Seq[Double] =
      args.flatMap(_.split("[,\\s]+").filter(_.nonEmpty)).map(number(_, line, what))

    private def expr(text: String, line: Int, what: String): BoolExpr =
      BoolExpr.parse(text).fold(msg => fail(line, s"bad $what: $msg"), identity)

    private def exprAttr(g: Group, attr: String, what: String): Option[BoolExpr] =
      g.simple(attr).map(a => expr(a.value, a.line, s"$attr of $what"))

    /** The factor of a unit string like `1ns` or `100ps` relative to the unit in `scales`. */
    private def unit(text: String, line: Int, what: String, scales: Map[String, Double]): Double = {
      val UnitText = """\s*([0-9.eE+-]+)\s*([A-Za-z]+)\s*""".r
      text match {
        case UnitText(n, u) if scales.contains(u.toLowerCase) => number(n, line, what) * scales(u.toLowerCase)
        case _ => fail(line, s"bad $what '$text'")
      }
    }

    def library(g: Group): Library = {
      val timeNs = g.simple("time_unit").fold(1.0)(a =>
        unit(a.value, a.line, "time_unit", Map("s" -> 1e9, "ms" -> 1e6, "us" -> 1e3, "ns" -> 1.0, "ps" -> 1e-3, "fs" -> 1e-6)))
      val capPf = g.complex("capacitive_load_unit").fold(1.0) { a =>
        a.args match {
          case Seq(n, u) => unit(n + u, a.line, "capacitive_load_unit", Map("nf" -> 1e3, "pf" -> 1.0, "ff" -> 1e-3))
          case _         => fail(a.line, "capacitive_load_unit takes (number, unit)")
        }
      }
      val leakNw = g.simple("leakage_power_unit").fold(1.0)(a =>
        unit(a.value, a.line, "leakage_power_unit", Map("w" -> 1e9, "mw" -> 1e6, "uw" -> 1e3, "nw" -> 1.0, "pw" -> 1e-3, "fw" -> 1e-6)))
      val cells = g.groups("cell").map(cell)
      val twice = cells.groupBy(_.name).collectFirst { case (n, cs) if cs.size > 1 => n }
      twice.foreach(n => fail(g.line, s"cell $n defined twice"))
      Library(g.args.headOption.getOrElse(""), timeNs, capPf, leakNw, cells.map(c => c.name -> c).toMap)
    }

    private def cell(g: Group): Cell = {
      val name = g.args.headOption.getOrElse(fail(g.line, "cell without a name"))
      val area = g.simple("area").fold(0.0)(a => number(a.value, a.line, s"area of cell $name"))
      val leakage = g.simple("cell_leakage_power").fold(0.0)(a => number(a.value, a.line, s"cell_leakage_power of cell $name"))
      val pins = g.groups("pin").flatMap(p => p.args.map(pinName => pin(p, pinName, name)))
      val ffs = g.groups("ff")
      val latches = g.groups("latch")
      if (ffs.size + latches.size > 1) fail(g.line, s"cell $name has more than one ff/latch group")
      Cell(name, area, leakage, pins, ffs.headOption.map(ff(_, name)), latches.headOption.map(latch(_, name)))
    }

    private def pin(g: Group, name: String, cellName: String): Pin = {
      val what = s"pin $name of cell $cellName"
      val direction = g.simple("direction") match {
        case Some(a) =>
          a.value match {
            case "input"    => Direction.Input
            case "output"   => Direction.Output
            case "inout"    => Direction.Inout
            case "internal" => Direction.Internal
            case other      => fail(a.line, s"bad direction '$other' of $what")
          }
        case None => fail(g.line, s"$what has no direction")
      }
      Pin(
        name,
        direction,
        g.simple("capacitance").fold(0.0)(a => number(a.value, a.line, s"capacitance of $what")),
        exprAttr(g, "function", what),
        exprAttr(g, "three_state", what),
        g.simple("clock").exists(_.value == "true"),
        g.groups("timing").map(timing(_, what)))
    }

    private def timing(g: Group, what: String): Timing = {
      val tables = g.body.collect {
        case t: Group if t.complex("values").isDefined =>
          val values = t.complex("values").get
          t.name -> Table(
            t.complex("index_1").fold(Seq.empty[Double])(a => numbers(a.args, a.line, s"index_1 of ${t.name} of $what")),
            t.complex("index_2").fold(Seq.empty[Double])(a => numbers(a.args, a.line, s"index_2 of ${t.name} of $what")),
            values.args.map(row => numbers(Seq(row), values.line, s"values of ${t.name} of $what")))
      }
      Timing(
        g.simple("related_pin").fold(Seq.empty[String])(_.value.split("\\s+").filter(_.nonEmpty).toSeq),
        g.simple("timing_type").map(_.value),
        g.simple("timing_sense").map(_.value),
        tables.toMap)
    }

    /** The two state variable names of an `ff`/`latch` group. */
    private def stateVars(g: Group, cellName: String): (String, String) = g.args match {
      case Seq(q, qn) => (q, qn)
      case _          => fail(g.line, s"${g.name} group of cell $cellName needs two state variable names")
    }

    private def ff(g: Group, cellName: String): Ff = {
      val (q, qn) = stateVars(g, cellName)
      val what = s"ff of cell $cellName"
      def required(attr: String): BoolExpr = exprAttr(g, attr, what).getOrElse(fail(g.line, s"$what has no $attr"))
      Ff(q, qn, required("next_state"), required("clocked_on"), exprAttr(g, "clear", what), exprAttr(g, "preset", what),
        g.simple("clear_preset_var1").map(_.value), g.simple("clear_preset_var2").map(_.value))
    }

    private def latch(g: Group, cellName: String): Latch = {
      val (q, qn) = stateVars(g, cellName)
      val what = s"latch of cell $cellName"
      Latch(q, qn, exprAttr(g, "data_in", what), exprAttr(g, "enable", what), exprAttr(g, "clear", what), exprAttr(g, "preset", what))
    }
  }
}
