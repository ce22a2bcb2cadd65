package mapm

import java.nio.charset.StandardCharsets.UTF_8
import java.nio.file.{Files, Path, Paths}

import org.scalatest.funsuite.AnyFunSuite
import scala.jdk.CollectionConverters._

/** The package layering of docs/architecture.md, read from the sources: which `mapm.<package>`
  * each main source file names (imports and qualified references, comments excluded). */
class ArchitectureSpec extends AnyFunSuite {
  private val src: Path = Paths.get(sys.props.getOrElse("mapm.root", ".")).resolve("src/main/scala/mapm")

  /** The source text without comments or string literals. */
  private def code(f: Path): String = {
    val s = new String(Files.readAllBytes(f), UTF_8)
    s.replaceAll("(?s)/\\*.*?\\*/", " ").replaceAll("//[^\n]*", " ").replaceAll("\"(?:\\\\.|[^\"\\\\])*\"", "\"\"")
  }

  /** package -> (file, code) of every main source file in a sub-package of mapm. */
  private lazy val files: Map[String, Seq[(Path, String)]] =
    Files.walk(src).iterator.asScala.filter(f => Files.isRegularFile(f) && f.toString.endsWith(".scala"))
      .filter(_.getParent != src).toSeq
      .map(f => (src.relativize(f).getName(0).toString, (f, code(f))))
      .groupMap(_._1)(_._2)

  private val ref = """\bmapm\.([a-z]+)\b""".r

  /** package -> the other mapm packages it names. */
  private lazy val deps: Map[String, Set[String]] =
    files.map { case (p, fs) => p -> fs.flatMap { case (_, c) => ref.findAllMatchIn(c).map(_.group(1)) }.toSet.filter(files.contains).-(p) }

  /** One cycle of the graph, if any (depth-first search). */
  private def cycle(g: Map[String, Set[String]]): Option[Seq[String]] = {
    val state = scala.collection.mutable.Map[String, Int]() // 1 on the path, 2 done
    def visit(n: String, path: List[String]): Option[Seq[String]] = state.get(n) match {
      case Some(1) => Some((n :: path).reverse.dropWhile(_ != n))
      case Some(_) => None
      case None =>
        state(n) = 1
        val found = g.getOrElse(n, Set.empty).toSeq.sorted.iterator.map(visit(_, n :: path)).collectFirst { case Some(c) => c }
        state(n) = 2
        found
    }
    g.keys.toSeq.sorted.iterator.map(visit(_, Nil)).collectFirst { case Some(c) => c }
  }

  test("the cycle finder finds a planted cycle and accepts a layered graph") {
    assert(cycle(Map("a" -> Set("b"), "b" -> Set("c"), "c" -> Set("a"))).map(_.toSet).contains(Set("a", "b", "c")))
    assert(cycle(Map("a" -> Set("b", "c"), "b" -> Set("c"), "c" -> Set.empty[String])).isEmpty)
  }

  private val hardware = Seq("util", "arith", "fpu", "params", "memory", "axi", "uncore", "tsearch", "shader", "top", "soc")

  /** The layering rules of docs/architecture.md, each a check of a package graph that returns its
    * violations (none for a good graph). */
  private val rules: Seq[(String, Map[String, Set[String]] => Seq[String])] = Seq(
    "no package cycle" -> (g => cycle(g).map(c => s"cycle ${c.mkString(" -> ")}").toSeq),
    "the hardware uses no host-side layer above it" -> (g =>
      for (p <- hardware; d <- g.getOrElse(p, Set.empty).toSeq.sorted if Set("sim", "cli", "cost", "fuzz")(d)) yield s"$p uses $d"),
    "the hardware uses the numerics, never the renderer" -> (g =>
      for (p <- hardware if g.getOrElse(p, Set.empty)("model")) yield s"$p uses model"),
    "the numerics sit at the bottom" -> (g => g.getOrElse("numerics", Set.empty).toSeq.sorted.map(d => s"numerics uses $d")),
    "the renderer uses the numerics alone" -> (g => (g.getOrElse("model", Set.empty) - "numerics").toSeq.sorted.map(d => s"model uses $d")),
    "the file formats and the parameters use no renderer" -> (g =>
      for (p <- Seq("format", "params"); d <- g.getOrElse(p, Set.empty).toSeq.sorted if !Set("numerics", "format")(d)) yield s"$p uses $d"))

  test("the sources are found") {
    assume(Files.isDirectory(src), s"$src not found")
    assert(Set("numerics", "model", "params", "top", "sim", "cli").subsetOf(files.keySet), files.keySet)
  }

  for ((rule, check) <- rules) {
    test(s"rule: $rule") {
      val bad = check(deps)
      assert(bad.isEmpty, s"${bad.mkString("; ")} (graph: $deps)")
    }
  }

  test("each rule fails on a planted violation of it") {
    val good = Map("numerics" -> Set.empty[String], "model" -> Set("numerics"), "format" -> Set("numerics"),
      "params" -> Set("numerics", "format"), "shader" -> Set("params", "numerics"), "sim" -> Set("shader", "model"), "cli" -> Set("sim"))
    val planted = Seq(
      good.updated("numerics", Set("cli")),                   // a cycle (cli -> sim -> model -> numerics -> cli)
      good.updated("shader", Set("params", "sim")),           // hardware using a host layer
      good.updated("shader", Set("params", "model")),         // hardware using the renderer
      good.updated("numerics", Set("format")),                // numerics not at the bottom
      good.updated("model", Set("numerics", "format")),       // the renderer using more than the numerics
      good.updated("format", Set("numerics", "model")))       // a file format using the renderer
    for (((rule, check), g) <- rules.zip(planted)) {
      assert(check(good).isEmpty, s"$rule: the good graph passes")
      assert(check(g).nonEmpty, s"$rule: the planted violation is found")
    }
  }

  test("the host-side layers import no Chisel") {
    for (p <- Seq("numerics", "model", "format", "cost", "fuzz"); (f, c) <- files.getOrElse(p, Nil))
      assert(!"""\bimport\s+(chisel3|chiseltest|circt)\b""".r.findFirstIn(c).isDefined, s"$f imports Chisel")
  }
}
