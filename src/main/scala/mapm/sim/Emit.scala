package mapm.sim

import java.nio.charset.StandardCharsets
import java.nio.file.{Files, Path}

/** Emitting SystemVerilog through CIRCT (firtool), the one path every user-facing command uses. */
object Emit {
  /** firtool options for every emission: no randomized initial values (the design resets what
    * needs it) and no debug-info comments, so the output is stable and lint-clean. */
  val firtoolOpts: Array[String] = Array("-disable-all-randomization", "-strip-debug-info")

  /** Extra options for Verilog that yosys reads (the cost flow): no `automatic logic` locals and no
    * packed arrays, which yosys' front end rejects. The logic is the same, only spelt plainer. */
  val synthesisOpts: Array[String] =
    Array("--lowering-options=disallowLocalVariables,disallowPackedArrays,locationInfoStyle=none")

  /** The SystemVerilog of `gen` as one string; `forSynthesis` spells it for yosys. */
  def systemVerilog(gen: => chisel3.RawModule, forSynthesis: Boolean = false): String = {
    val sv = try circt.stage.ChiselStage.emitSystemVerilog(gen, Array.empty,
      if (forSynthesis) firtoolOpts ++ synthesisOpts else firtoolOpts)
    catch { // Chisel's FirtoolNonZeroExitCode, which it does not export
      case e: RuntimeException if e.getClass.getName.endsWith("FirtoolNonZeroExitCode") => mapm.MapmError.fail(firtoolFailure(e.getMessage))
    }
    // Black boxes with inline Verilog ([[mapm.util.ClockGate]]) come after the design, each after a
    // `// ----- 8< ----- FILE` comment; the file list that firtool appends last is not Verilog.
    val fileList = sv.indexOf(BlackBoxFileList)
    if (fileList < 0) sv else sv.substring(0, sv.lastIndexOf('\n', fileList) + 1)
  }

  /** One line for a failed firtool run, from Chisel's many-line message: its exit code (137 and
    * 9: killed, which on a big design is the kernel's out-of-memory killer) and the first line of
    * its error output. */
  def firtoolFailure(message: String): String = {
    val code = "(?s)ExitCode:\\s*(-?\\d+)".r.findFirstMatchIn(message).map(_.group(1).toInt)
    val err = "(?s)STDERR:\\s*\\n(.*)".r.findFirstMatchIn(message).map(_.group(1)).toSeq
      .flatMap(_.linesIterator.map(_.trim)).find(l => l.nonEmpty && !l.startsWith("---"))
    val why = code match {
      case Some(137) | Some(-9) | Some(9) => " (killed: most likely out of memory; a smaller configuration or a machine with more memory may emit)"
      case _ => ""
    }
    s"firtool failed with exit code ${code.fold("?")(_.toString)}$why${err.fold("")(l => s": $l")}"
  }

  private val BlackBoxFileList = "// ----- 8< ----- FILE \"firrtl_black_box_resource_files.f\""

  /** Writes the SystemVerilog of `gen` to `dir/<file>` and returns the path. */
  def toFile(gen: => chisel3.RawModule, dir: Path, file: String, forSynthesis: Boolean = false): Path = {
    Files.createDirectories(dir)
    val p = dir.resolve(file)
    Files.write(p, systemVerilog(gen, forSynthesis).getBytes(StandardCharsets.UTF_8))
    p
  }

  /** A port of an emitted module. */
  final case class Port(name: String, width: Int, isInput: Boolean)

  private val moduleRe = """(?m)^module\s+(\w+)\s*\(""".r
  // firtool writes `input [7:0] a,` and continues with bare `b,` lines that share the previous
  // declaration's direction and width.
  private val portRe = """^\s*(input|output)?\s*(?:wire\s+|logic\s+)?(?:\[(\d+):0\]\s*)?(\w+)\s*,?\s*(//.*)?$""".r

  /** The top module of an emitted file (the one no other module instantiates) and its ports in
    * declaration order. Throws if the text has no module. */
  def topPorts(sv: String): (String, Seq[Port]) = {
    val names = moduleRe.findAllMatchIn(sv).map(_.group(1)).toSeq
    require(names.nonEmpty, "no module in the emitted SystemVerilog")
    val instantiated = names.filter(n => s"""(?m)^\\s+$n\\s+\\w+\\s*\\(""".r.findFirstIn(sv).isDefined).toSet
    val top = names.filterNot(instantiated).lastOption.getOrElse(names.last)
    val start = sv.indexOf(s"module $top")
    val header = sv.substring(start, sv.indexOf(");", start))
    var lastDir = "input"
    var lastWidth = 1
    val ports = header.linesIterator.drop(1).flatMap {
      case portRe(dir, hi, name, _) =>
        if (dir != null) { lastDir = dir; lastWidth = if (hi == null) 1 else hi.toInt + 1 }
        else if (hi != null) lastWidth = hi.toInt + 1
        Some(Port(name, lastWidth, lastDir == "input"))
      case _ => None
    }.toSeq
    (top, ports)
  }
}
