package mapm.cost

import mapm.MapmError
import scala.collection.mutable.ArrayBuffer

/** The syntax of Liberty (.lib) files: any Liberty text as a tree of [[LibertySyntax.Group]]s
  * (`name (args) { ... }`), [[LibertySyntax.SimpleAttribute]]s (`name : value ;`) and
  * [[LibertySyntax.ComplexAttribute]]s (`name (args) ;`), with `/* */` and `//` comments dropped and
  * lines ended by `\` joined. [[Liberty]] reads the cells from it. */
object LibertySyntax {
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

  /** The `library` group of Liberty `text`; `source` names it in error messages. */
  def parse(text: String, source: String): Group = {
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
}
