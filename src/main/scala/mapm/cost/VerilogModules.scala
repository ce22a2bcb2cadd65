package mapm.cost

/** The modules of a netlist that yosys' `write_verilog` wrote, as text, and port-only shells of
  * them: the cost flow analyses a large module's own logic with its submodules as empty shells. */
object VerilogModules {
  private val startRe = """(?m)^module\s+\\?(\S+?)\s*\(""".r

  /** Each module's text, from `module` to `endmodule`, by name. */
  def split(text: String): Map[String, String] =
    startRe.findAllMatchIn(text).map { m =>
      val end = text.indexOf("endmodule", m.start)
      m.group(1) -> text.substring(m.start, if (end < 0) text.length else end + "endmodule".length)
    }.toMap

  /** The module with its header and port declarations only: no cells, no paths. */
  def shell(module: String): String = {
    val header = module.substring(0, module.indexOf(';') + 1)
    val ports = module.linesIterator.map(_.trim).filter(l => l.startsWith("input") || l.startsWith("output") || l.startsWith("inout"))
    (header +: ports.toSeq :+ "endmodule").mkString("\n")
  }
}
