package mapm.cost

import mapm.MapmError

/** The module hierarchy of an emitted (CIRCT) Verilog file, read from its text: which modules
  * instantiate which, and which modules are memory arrays (firtool's `reg [W-1:0] Memory[0:D-1]`
  * modules for `SyncReadMem`s), with their bits.
  *
  * @param children per module, the modules it instantiates (one entry per instance)
  * @param memories per memory module, (width, depth)
  */
final case class Hierarchy(children: Map[String, Seq[String]], memories: Map[String, (Int, Int)]) {
  /** Bits of memory module `m`. */
  def memoryBits(m: String): Long = memories.get(m).map { case (w, d) => w.toLong * d }.getOrElse(0L)
}

object Hierarchy {
  private val moduleRe = """(?m)^module\s+(\w+)\s*[(#]""".r
  private val instRe = """(?m)^\s+(\w+)\s+(?:#\s*\(.*?\)\s*)?(\w+)\s*\(""".r
  private val memRe = """reg\s*\[(\d+):0\]\s*Memory\s*\[0:(\d+)\]""".r

  def parse(sv: String): Hierarchy = {
    val starts = moduleRe.findAllMatchIn(sv).toSeq
    MapmError.check(starts.nonEmpty, "cost: no module in the Verilog")
    val names = starts.map(_.group(1)).toSet
    val bodies = starts.zipWithIndex.map { case (m, i) =>
      val end = if (i + 1 < starts.size) starts(i + 1).start else sv.length
      m.group(1) -> sv.substring(m.end, end)
    }
    val children = bodies.map { case (n, body) =>
      n -> instRe.findAllMatchIn(body).map(_.group(1)).filter(names.contains).toSeq
    }.toMap
    val memories = bodies.flatMap { case (n, body) =>
      memRe.findFirstMatchIn(body).map(m => n -> (m.group(1).toInt + 1, m.group(2).toInt + 1))
    }.toMap
    Hierarchy(children, memories)
  }
}
