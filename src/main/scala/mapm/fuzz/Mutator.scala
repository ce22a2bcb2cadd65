package mapm.fuzz

import java.nio.charset.StandardCharsets.UTF_8

import scala.util.Random

/** Seeded generators of hostile input files for the scene readers ([[LoaderFuzz]]): mutations of a
  * valid text (byte, token, line and structure edits), random bytes, truncations, extreme numbers
  * and deep nesting. Every generator is a pure function of its [[Random]], so a failing input is
  * regenerated from its seed alone. */
object Mutator {
  /** Numbers that break naive parsers: huge, tiny, signed zeros, special values, integers just
    * past 32 and 64 bits, long digit strings. */
  val ExtremeNumbers: IndexedSeq[String] = IndexedSeq(
    "0", "-0", "1e308", "-1e308", "1e309", "1e-320", "4.9e-324", "NaN", "nan", "Infinity", "-inf", "inf",
    "2147483647", "2147483648", "-2147483649", "9223372036854775807", "9223372036854775808", "1" * 400,
    "0x1p3", "1e", "--1", "+", ".", "1..2", "1e+99999", "-", "0.000000000000000000000000001", "3.4028235e38", "16777217")

  /** Tokens of the OBJ and MTL languages, and some that are not. */
  val ObjTokens: IndexedSeq[String] = IndexedSeq(
    "v", "f", "vt", "vn", "usemtl", "mtllib", "newmtl", "Kd", "Ke", "Ns", "g", "o", "s", "#", "\\", "/", "//", "-1", "0",
    "1/2/3", "white", "cornell-box.mtl", "missing.mtl", "../cornell-box.mtl", "curv", "\t", "\u0000", "\u00e9", "\uffff")

  /** A random printable-or-not string of up to `n` characters. */
  def randomText(r: Random, n: Int): String =
    Seq.fill(r.nextInt(n + 1))(r.nextInt(10) match {
      case 0 => '\n'
      case 1 => ' '
      case 2 => (r.nextInt(0x2ff) + 1).toChar
      case _ => (r.nextInt(95) + 32).toChar
    }).mkString

  /** `n` random bytes (not necessarily UTF-8). */
  def randomBytes(r: Random, n: Int): Array[Byte] = Array.fill(r.nextInt(n + 1))(r.nextInt(256).toByte)

  /** One random edit of `text`'s lines or tokens (`tokens`: words of its language to insert). */
  def mutateText(r: Random, text: String, tokens: IndexedSeq[String]): String = {
    val lines = text.split("\n", -1).toIndexedSeq
    def line = r.nextInt(lines.size)
    def token = if (r.nextBoolean()) tokens(r.nextInt(tokens.size)) else ExtremeNumbers(r.nextInt(ExtremeNumbers.size))
    r.nextInt(10) match {
      case 0 => // delete a line
        val i = line; (lines.take(i) ++ lines.drop(i + 1)).mkString("\n")
      case 1 => // duplicate a line, sometimes many times
        val i = line; (lines.take(i) ++ Seq.fill(1 + r.nextInt(if (r.nextInt(20) == 0) 2000 else 3))(lines(i)) ++ lines.drop(i)).mkString("\n")
      case 2 => // replace a word of a line
        val i = line
        val words = lines(i).split(" ", -1)
        val j = r.nextInt(words.length)
        lines.updated(i, words.updated(j, token).mkString(" ")).mkString("\n")
      case 3 => // insert a word into a line
        val i = line
        val words = lines(i).split(" ", -1).toIndexedSeq
        val j = r.nextInt(words.size + 1)
        lines.updated(i, (words.take(j) ++ Seq(token) ++ words.drop(j)).mkString(" ")).mkString("\n")
      case 4 => // insert a random statement line
        val i = line
        val stmt = (Seq(tokens(r.nextInt(tokens.size))) ++ Seq.fill(r.nextInt(6))(token)).mkString(" ")
        (lines.take(i) ++ Seq(stmt) ++ lines.drop(i)).mkString("\n")
      case 5 => // truncate
        text.take(r.nextInt(text.length + 1))
      case 6 => // flip characters
        val cs = text.toCharArray
        for (_ <- 0 to r.nextInt(4) if cs.nonEmpty) cs(r.nextInt(cs.length)) = (r.nextInt(0x3000)).toChar
        new String(cs)
      case 7 => // swap two lines
        val (i, j) = (line, line); lines.updated(i, lines(j)).updated(j, lines(i)).mkString("\n")
      case 8 => // insert random text
        val at = r.nextInt(text.length + 1); text.take(at) + randomText(r, 40) + text.drop(at)
      case _ => // a line continued onto the next
        val i = line; lines.updated(i, lines(i) + " \\").mkString("\n")
    }
  }

  /** A random JSON value, nested up to `depth` levels. */
  def randomJson(r: Random, depth: Int): ujson.Value = r.nextInt(if (depth <= 0) 5 else 7) match {
    case 0 => ujson.Num(ExtremeNumbers(r.nextInt(ExtremeNumbers.size)).toDoubleOption.getOrElse(r.nextGaussian() * 1e6))
    case 1 => ujson.Num(r.nextInt(200) - 50)
    case 2 => ujson.Str(Seq("point", "area", "fp32", "fp16", "e5,m4", "auto", "cornell-box.obj", "", "x" * r.nextInt(50))(r.nextInt(9)))
    case 3 => ujson.Bool(r.nextBoolean())
    case 4 => ujson.Null
    case 5 => ujson.Arr.from(Seq.fill(r.nextInt(5))(randomJson(r, depth - 1)))
    case _ => ujson.Obj.from(Seq.fill(r.nextInt(4))(Seq("type", "auto", "position", "x", "power")(r.nextInt(5)) -> randomJson(r, depth - 1)))
  }

  /** One random structural edit of a JSON document: replace, remove or add a value somewhere. */
  def mutateJson(r: Random, v: ujson.Value): ujson.Value = {
    def edit(x: ujson.Value, keys: IndexedSeq[String]): ujson.Value = x match {
      case o: ujson.Obj if o.value.nonEmpty && r.nextInt(3) != 0 =>
        val ks = o.value.keys.toIndexedSeq
        val k = ks(r.nextInt(ks.size))
        val copy = ujson.Obj.from(o.value.toSeq)
        r.nextInt(4) match {
          case 0 => copy.value.remove(k)
          case 1 => copy(keys(r.nextInt(keys.size))) = randomJson(r, 3)
          case _ => copy(k) = edit(o.value(k), keys)
        }
        copy
      case a: ujson.Arr if a.value.nonEmpty && r.nextInt(3) != 0 =>
        val i = r.nextInt(a.value.size)
        val copy = ujson.Arr.from(a.value.toSeq)
        r.nextInt(4) match {
          case 0 => copy.value.remove(i)
          case 1 => copy.value.insert(i, randomJson(r, 2))
          case _ => copy(i) = edit(a.value(i), keys)
        }
        copy
      case _ => randomJson(r, 3)
    }
    edit(v, IndexedSeq("obj", "camera", "lights", "width", "height", "finalGatherRays", "photons", "maxBounces", "h", "seed",
      "format", "defaultKd", "directLightSamples", "comment", "lookAt", "fov", "unknownKey"))
  }

  /** `depth` nested arrays or objects around a value (a parser's recursion limit). */
  def deepJson(r: Random, depth: Int): String = {
    val (open, close) = if (r.nextBoolean()) ("[", "]") else ("{\"a\":", "}")
    open * depth + "1" + (if (r.nextBoolean()) close * depth else close * r.nextInt(depth + 1))
  }

  def bytes(s: String): Array[Byte] = s.getBytes(UTF_8)
}
