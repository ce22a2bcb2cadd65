package mapm.fpu

import java.nio.file.Files
import mapm.sim.{Emit, Verilator}
import scala.sys.process._

/** Verilator lint (`--lint-only -Wall`) of a design's emitted SystemVerilog, one file per module
  * (firtool `--split-verilog`), so that every warning class, file naming included, applies. */
object LintCheck {
  /** The lint messages for `gen` (empty when clean) and the top module's name. */
  def apply(gen: => chisel3.RawModule): (String, Seq[String]) = {
    val dir = Files.createTempDirectory("lint")
    circt.stage.ChiselStage.emitSystemVerilog(gen, Array.empty[String],
      Emit.firtoolOpts ++ Array("--split-verilog", "-o", dir.toString))
    val files = dir.toFile.listFiles().filter(_.getName.endsWith(".sv")).map(_.getName).sorted
    require(files.nonEmpty, s"nothing emitted into $dir")
    val (top, _) = Emit.topPorts(files.map(f => new String(Files.readAllBytes(dir.resolve(f)), "UTF-8")).mkString("\n"))
    val log = new StringBuilder
    val rc = Process(Seq(Verilator.executable, "--lint-only", "-Wall", "--top-module", top) ++ files, dir.toFile)
      .!(ProcessLogger(l => log.append(l).append('\n'), l => log.append(l).append('\n')))
    val messages = log.toString.linesIterator.filter(_.startsWith("%")).toSeq
    (top, if (rc != 0 && messages.isEmpty) Seq(s"verilator exited with $rc") else messages)
  }
}
