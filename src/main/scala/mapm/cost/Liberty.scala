package mapm.cost

import java.nio.charset.StandardCharsets
import java.nio.file.{Files, Path}
import mapm.MapmError
import scala.collection.mutable.ArrayBuffer

/** Liberty (.lib) cell libraries.
  *
  * Two layers. [[Liberty.parseSyntax]] reads any Liberty text into a tree of [[Liberty.Group]]s
  * (`name (args) { ... }`), [[Liberty.SimpleAttribute]]s (`name : value ;`) and
  * [[Liberty.ComplexAttribute]]s (`name (args) ;`); it drops `/* */` and `//` comments and joins
  * lines ended by `\`. [[Liberty.read]] and [[Liberty.parse]] then give the typed view a gate-level
  * flow needs: units, and per cell its area, leakage, pins (direction, capacitance, function,
  * timing tables) and its `ff`/`latch` group.
  *
  * Not read: `bus` and `bundle` pins, `statetable`, `ff_bank`/`latch_bank`, per-state
  * `leakage_power` groups, power tables and operating conditions.
  */
object Liberty {
  /** One statement of a Liberty file; `line` is where its name stands (1-based). */
  sealed trait Statement {
    def name: String
    def line: Int
  }

  /** `name : value ;`. A quoted value is kept without its quotes. */
  final case class SimpleAttribute(name: String, value: String, line: Int) extends Statement

  /** `name (args) ;`. Quoted arguments are kept without their quotes. */
  final case class ComplexAttribute(name: String, args: Seq[String], line: Int) extends Statement

  /** `name (args) { body }`. */
  final case class Group(name: String, args: Seq[String], body: Seq[Statement], line: Int) extends Statement {
    /** The sub-groups called `kind`, in file order. */
    def groups(kind: String): Seq[Group] = body.collect { case g: Group if g.name == kind => g }

    /** The simple attribute `attr`, if there is one (the last one if repeated). */
    def simple(attr: String): Option[SimpleAttribute] =
      body.reverseIterator.collectFirst { case a: SimpleAttribute if a.name == attr => a }

    /** The complex attribute `attr`, if there is one (the last one if repeated). */
    def complex(attr: String): Option[ComplexAttribute] =
      body.reverseIterator.collectFirst { case a: ComplexAttribute if a.name == attr => a }
  }

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
  def parse(text: String, source: String): Library = new TypedView(source).library(parseSyntax(text, source))

  /** The `library` group of Liberty `text`; `source` names it in error messages. */
  def parseSyntax(text: String, source: String): Group = {
    val statements = new SyntaxParser(new Lexer(text, source).tokens(), source).file()
    statements match {
      case Seq(g: Group) if g.name == "library" => g
      case _ => MapmError.fail(s"$source: not a Liberty library (expected one 'library (name) { ... }' group)")
    }
  }

  /** A token: a word (name, number, unquoted value), a quoted string, or one of `(){}:;,`. */
  private final case class Token(kind: Token.Kind, text: String, line: Int)

  /** The kinds of [[Token]]. */
  private object Token {
    sealed trait Kind
    case object Word extends Kind
    case object Quoted extends Kind
    case object Punct extends Kind
  }

  /** Splits Liberty text into [[Token]]s, dropping comments and `\`-newline continuations. */
  private final class Lexer(text: String, source: String) {
    private var pos = 0
    private var line = 1

    private def isPunct(c: Char): Boolean = "(){}:;,".indexOf(c.toInt) >= 0

    private def at(s: String): Boolean = text.startsWith(s, pos)

    /** Whether a `\` at `pos` ends its line (only blanks between it and the newline). */
    private def continuationAt: Boolean = text(pos) == '\\' && {
      var i = pos + 1
      while (i < text.length && (text(i) == ' ' || text(i) == '\t' || text(i) == '\r')) i += 1
      i == text.length || text(i) == '\n'
    }

    /** Skips blanks, newlines, comments and continuations. */
    private def skip(): Unit = {
      var moved = true
      while (moved && pos < text.length) {
        val c = text(pos)
        if (c == '\n') { line += 1; pos += 1 }
        else if (c.isWhitespace) pos += 1
        else if (at("/*")) {
          val end = text.indexOf("*/", pos + 2)
          if (end < 0) MapmError.fail(s"$source:$line: unterminated comment")
          line += text.substring(pos, end).count(_ == '\n')
          pos = end + 2
        } else if (at("//")) { while (pos < text.length && text(pos) != '\n') pos += 1 }
        else if (continuationAt) pos += 1
        else moved = false
      }
    }

    def tokens(): ArrayBuffer[Token] = {
      val out = ArrayBuffer.empty[Token]
      skip()
      while (pos < text.length) {
        val c = text(pos)
        if (isPunct(c)) { out += Token(Token.Punct, c.toString, line); pos += 1 }
        else if (c == '"') out += quoted()
        else {
          val start = pos
          while (pos < text.length && !text(pos).isWhitespace && !isPunct(text(pos)) && text(pos) != '"' &&
                 !at("/*") && !continuationAt) pos += 1
          out += Token(Token.Word, text.substring(start, pos), line)
        }
        skip()
      }
      out
    }

    /** A `"..."` string; a `\`-newline inside it is dropped, `\"` is a quote. */
    private def quoted(): Token = {
      val startLine = line
      val sb = new StringBuilder
      pos += 1
      while (pos < text.length && text(pos) != '"') {
        if (continuationAt) {
          while (text(pos) != '\n') pos += 1
          line += 1
        } else if (text(pos) == '\\' && pos + 1 < text.length && text(pos + 1) == '"') { sb += '"'; pos += 1 }
        else {
          if (text(pos) == '\n') line += 1
          sb += text(pos)
        }
        pos += 1
      }
      if (pos >= text.length) MapmError.fail(s"$source:$startLine: unterminated string")
      pos += 1
      Token(Token.Quoted, sb.toString, startLine)
    }
  }

  /** Recursive descent over [[Token]]s into [[Statement]]s. */
  private final class SyntaxParser(tokens: ArrayBuffer[Token], source: String) {
    private var i = 0

    private def lastLine: Int = if (tokens.isEmpty) 1 else tokens.last.line

    private def fail(line: Int, what: String): Nothing = MapmError.fail(s"$source:$line: $what")

    private def isPunct(k: Int, p: String): Boolean = k < tokens.length && tokens(k).kind == Token.Punct && tokens(k).text == p

    private def isValue(k: Int): Boolean = k < tokens.length && tokens(k).kind != Token.Punct

    def file(): Seq[Statement] = {
      val out = ArrayBuffer.empty[Statement]
      while (i < tokens.length) out += statement()
      out.toSeq
    }

    private def statement(): Statement = {
      val nameToken = tokens(i)
      if (nameToken.kind != Token.Word) fail(nameToken.line, s"expected a name, found '${nameToken.text}'")
      i += 1
      if (isPunct(i, ":")) {
        i += 1
        if (!isValue(i)) fail(nameToken.line, s"missing value of attribute '${nameToken.text}'")
        // a value runs to ';' (which some files leave out at the end of a line)
        val valueLine = tokens(i).line
        val parts = ArrayBuffer.empty[String]
        while (isValue(i) && tokens(i).line == valueLine) { parts += tokens(i).text; i += 1 }
        if (isPunct(i, ";")) i += 1
        SimpleAttribute(nameToken.text, parts.mkString(" "), nameToken.line)
      } else if (isPunct(i, "(")) {
        i += 1
        val args = ArrayBuffer.empty[String]
        while (!isPunct(i, ")")) {
          if (i >= tokens.length) fail(nameToken.line, s"missing ')' after the arguments of '${nameToken.text}'")
          if (isValue(i)) args += tokens(i).text
          else if (!isPunct(i, ",")) fail(tokens(i).line, s"unexpected '${tokens(i).text}' in the arguments of '${nameToken.text}'")
          i += 1
        }
        i += 1
        if (isPunct(i, "{")) {
          i += 1
          val body = ArrayBuffer.empty[Statement]
          while (!isPunct(i, "}")) {
            if (i >= tokens.length) fail(lastLine, s"missing '}' of group '${nameToken.text}' opened on line ${nameToken.line}")
            body += statement()
          }
          i += 1
          Group(nameToken.text, args.toSeq, body.toSeq, nameToken.line)
        } else {
          if (isPunct(i, ";")) i += 1
          ComplexAttribute(nameToken.text, args.toSeq, nameToken.line)
        }
      } else fail(nameToken.line, s"expected ':' or '(' after '${nameToken.text}'")
    }
  }

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
