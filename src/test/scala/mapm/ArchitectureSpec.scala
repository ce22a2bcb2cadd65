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

  test("the sources are found") {
    assume(Files.isDirectory(src), s"$src not found")
    assert(Set("model", "params", "top", "sim", "cli").subsetOf(files.keySet), files.keySet)
  }

  test("no package cycle") {
    assert(cycle(deps).isEmpty, s"package cycle: ${cycle(deps).map(_.mkString(" -> ")).getOrElse("")}; graph: $deps")
  }

  test("the host-side layers import no Chisel") {
    for (p <- Seq("model", "format", "cost", "fuzz"); (f, c) <- files.getOrElse(p, Nil))
      assert(!"""\bimport\s+(chisel3|chiseltest|circt)\b""".r.findFirstIn(c).isDefined, s"$f imports Chisel")
  }

  test("hardware packages depend on none of the host-side layers above them") {
    val host = Set("sim", "cli", "cost", "fuzz")
    for (p <- Seq("util", "arith", "fpu", "params", "memory", "tsearch", "shader", "top"))
      assert((deps.getOrElse(p, Set.empty) & host).isEmpty, s"$p depends on ${deps(p) & host}")
  }

  test("the model, the file formats and the parameters sit at the bottom") {
    assert(deps.getOrElse("model", Set.empty).isEmpty, s"model depends on ${deps("model")}")
    assert(deps.getOrElse("format", Set.empty).subsetOf(Set("model")), s"format depends on ${deps("format")}")
    assert(deps.getOrElse("params", Set.empty).subsetOf(Set("model", "format")), s"params depends on ${deps("params")}")
  }
}
