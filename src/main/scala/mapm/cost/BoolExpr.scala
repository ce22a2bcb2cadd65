package mapm.cost

/** A Boolean function of named variables, as a Liberty file writes one in a `function`,
  * `next_state`, `clocked_on`, `clear` ... string: the variables are pin names or the state
  * variables of an `ff`/`latch` group.
  */
sealed trait BoolExpr {
  import BoolExpr._

  /** The value under an assignment of the variables. */
  def eval(env: String => Boolean): Boolean = this match {
    case Const(v)  => v
    case Var(name) => env(name)
    case Not(e)    => !e.eval(env)
    case And(a, b) => a.eval(env) && b.eval(env)
    case Or(a, b)  => a.eval(env) || b.eval(env)
    case Xor(a, b) => a.eval(env) ^ b.eval(env)
  }

  /** The names of the variables it reads. */
  def vars: Set[String] = this match {
    case Const(_)  => Set.empty
    case Var(name) => Set(name)
    case Not(e)    => e.vars
    case And(a, b) => a.vars ++ b.vars
    case Or(a, b)  => a.vars ++ b.vars
    case Xor(a, b) => a.vars ++ b.vars
  }
}

/** The cases of [[BoolExpr]] and the parser of Liberty's syntax for them.
  *
  * Syntax (Liberty's): `!x` and `x'` are NOT; `x & y`, `x * y` and `x y` (juxtaposition) are AND;
  * `x ^ y` is XOR; `x | y` and `x + y` are OR; parentheses group; `0` and `1` are the constants;
  * any other name (letters, digits, `_`, `[`, `]`, `.`, starting with a letter or `_`) is a
  * variable. Precedence from tightest: NOT, AND, XOR, OR; binary operators group to the left.
  */
object BoolExpr {
  /** The constant `value`. */
  final case class Const(value: Boolean) extends BoolExpr

  /** The variable (pin or state variable) `name`. */
  final case class Var(name: String) extends BoolExpr

  /** The complement of `e`. */
  final case class Not(e: BoolExpr) extends BoolExpr

  /** `a` AND `b`. */
  final case class And(a: BoolExpr, b: BoolExpr) extends BoolExpr

  /** `a` OR `b`. */
  final case class Or(a: BoolExpr, b: BoolExpr) extends BoolExpr

  /** `a` XOR `b`. */
  final case class Xor(a: BoolExpr, b: BoolExpr) extends BoolExpr

  /** Parses a Liberty Boolean function; Left with what is wrong and where (a 1-based column). */
  def parse(text: String): Either[String, BoolExpr] =
    try Right(new Parser(text).whole())
    catch { case e: Parser.Failure => Left(e.getMessage) }

  /** Recursive descent over the characters of one function string. */
  private final class Parser(text: String) {
    private var pos = 0

    private def skipSpace(): Unit = while (pos < text.length && text(pos).isWhitespace) pos += 1

    private def peek: Option[Char] = { skipSpace(); if (pos < text.length) Some(text(pos)) else None }

    private def fail(what: String): Nothing = throw new Parser.Failure(s"$what at column ${pos + 1} of \"$text\"")

    private def isNameStart(c: Char): Boolean = c.isLetterOrDigit || c == '_'

    private def isNameChar(c: Char): Boolean = c.isLetterOrDigit || c == '_' || c == '[' || c == ']' || c == '.'

    def whole(): BoolExpr = {
      val e = or()
      if (peek.nonEmpty) fail(s"unexpected '${text(pos)}'")
      e
    }

    private def or(): BoolExpr = {
      var e = xor()
      while (peek.exists(c => c == '|' || c == '+')) { pos += 1; e = Or(e, xor()) }
      e
    }

    private def xor(): BoolExpr = {
      var e = and()
      while (peek.contains('^')) { pos += 1; e = Xor(e, and()) }
      e
    }

    private def and(): BoolExpr = {
      var e = unary()
      var more = true
      while (more) peek match {
        case Some('&') | Some('*')                                  => pos += 1; e = And(e, unary())
        case Some(c) if c == '!' || c == '(' || isNameStart(c) => e = And(e, unary()) // juxtaposition
        case _                                                      => more = false
      }
      e
    }

    private def unary(): BoolExpr =
      if (peek.contains('!')) { pos += 1; Not(unary()) }
      else {
        var e = primary()
        while (peek.contains('\'')) { pos += 1; e = Not(e) }
        e
      }

    private def primary(): BoolExpr = peek match {
      case Some('(') =>
        pos += 1
        val e = or()
        if (!peek.contains(')')) fail("missing ')'")
        pos += 1
        e
      case Some(c) if isNameStart(c) =>
        val start = pos
        while (pos < text.length && isNameChar(text(pos))) pos += 1
        text.substring(start, pos) match {
          case "0"                         => Const(false)
          case "1"                         => Const(true)
          case name if name.head.isDigit => pos = start; fail(s"bad name '$name'")
          case name                        => Var(name)
        }
      case Some(c) => fail(s"unexpected '$c'")
      case None    => fail("unexpected end")
    }
  }

  private object Parser {
    /** A syntax error inside [[Parser]]; [[BoolExpr.parse]] turns it into a Left. */
    final class Failure(message: String) extends Exception(message)
  }
}
