package mapm.testutil

import java.nio.file.{Files, Path, Paths}

import scala.sys.process._

/** The host programs some specs need (Verilator, g++): whether one is on PATH, so a spec can
  * cancel with a message without it, and a g++ build of a small C++ driver. */
object HostTools {
  /** Whether an executable `tool` is on PATH. */
  def onPath(tool: String): Boolean =
    sys.env.getOrElse("PATH", "").split(java.io.File.pathSeparator).exists(d => Files.isExecutable(Paths.get(d, tool)))

  /** Compiles `source` (C++17, -Wall -Werror, `flags`) into `dir/name` with the include folders
    * `includes`; fails the calling test with g++'s output when it does not compile. */
  def gpp(dir: Path, name: String, source: String, includes: Seq[Path], flags: Seq[String] = Nil): Path = {
    Files.createDirectories(dir)
    val src = dir.resolve(s"$name.cpp")
    Files.write(src, source.getBytes("UTF-8"))
    val out = dir.resolve(name)
    val log = new StringBuilder
    val rc = (Seq("g++", "-std=c++17", "-Wall", "-Werror") ++ flags ++ includes.flatMap(i => Seq("-I", i.toString)) ++
      Seq("-o", out.toString, src.toString)).!(ProcessLogger(l => log.append(l).append('\n')))
    org.scalatest.Assertions.assert(rc == 0, s"g++ failed on $src:\n$log")
    out
  }
}
