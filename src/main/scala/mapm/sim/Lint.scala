package mapm.sim

import java.nio.file.Path

import mapm.MapmError
import scala.sys.process._

/** Verilator's lint (`--lint-only -Wall`) of an emitted design: the whole MAPM's single file (so
  * DECLFILENAME, one module per file, is off). */
object Lint {
  /** The lint messages (empty when clean) of the design in `files` whose top is `top`. */
  def warnings(files: Seq[Path], top: String): Seq[String] = {
    MapmError.check(files.nonEmpty, s"lint of $top: no Verilog files")
    val log = new StringBuilder
    val rc = Process(Seq(Verilator.executable, "--lint-only", "-Wall", "-Wno-DECLFILENAME", "--top-module", top) ++ files.map(_.toString))
      .!(ProcessLogger(l => log.append(l).append('\n'), l => log.append(l).append('\n')))
    val messages = log.toString.linesIterator.filter(_.startsWith("%")).toSeq
    if (rc != 0 && messages.isEmpty) Seq(s"verilator exited with $rc: ${log.toString.linesIterator.take(3).mkString(" | ")}") else messages
  }
}
