package mapm.sim

/** Figures read from emitted SystemVerilog text. */
object SvStats {
  private val moduleRe = """(?s)\bmodule\s+(\w+)\s*\((.*?)\bendmodule\b""".r
  private val regRe = """(?m)^\s*reg\s+(?:\[(\d+):(\d+)\]\s*)?(\w+)\s*;""".r
  private val instRe = """(?m)^\s+(\w+)\s+\w+\s*\(""".r

  /** The names of the modules defined in `sv`, in text order. */
  def modules(sv: String): Seq[String] = moduleRe.findAllMatchIn(sv).map(_.group(1)).toSeq

  /** Flip-flop bits of the module `top`, counting every
    * `reg` declaration of each module once per instance in the hierarchy. The latch of a clock gate
    * ([[mapm.util.ClockGate]], whose module has an `always_latch`) is not a flip-flop. */
  def registerBits(sv: String, top: String): Long = {
    val bodies = moduleRe.findAllMatchIn(sv).map(m => m.group(1) -> m.group(2)).toMap
    val memo = scala.collection.mutable.Map.empty[String, Long]
    def count(name: String): Long = memo.getOrElseUpdate(name, {
      val body = bodies(name)
      val own = if (body.contains("always_latch")) 0L else regRe.findAllMatchIn(body).map { m =>
        if (m.group(1) == null) 1L else (m.group(1).toLong - m.group(2).toLong).abs + 1
      }.sum
      own + instRe.findAllMatchIn(body).map(_.group(1)).filter(bodies.contains).map(count).sum
    })
    count(top)
  }
}
