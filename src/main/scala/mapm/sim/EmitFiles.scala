package mapm.sim

import java.nio.charset.StandardCharsets.UTF_8
import java.nio.file.{Files, Path}

/** The files `mapm emit` writes for an ASIC or FPGA flow, read from firtool's SystemVerilog: the
  * design split in three, so that a flow can swap the parts it must replace,
  *  - `<top>.sv`: the design itself;
  *  - `<top>_memories.sv`: firtool's behavioural models of the memories (a `Memory` array with
  *    registered read ports), for a memory compiler's macros or an FPGA's block RAM to replace;
  *  - `<top>_blackboxes.sv`: the black boxes' behavioural models (the [[mapm.util.ClockGate]]
  *    latch), for the library's own cells to replace;
  * `<top>.f`, the file list in compile order; `<top>_memories.conf`, the memories in the line
  * format of firtool's `--repl-seq-mem` (`name N depth D width W ports P [mask_gran G]`), which
  * memory-compiler scripts such as Chipyard's MacroCompiler read; and `<top>_manifest.json`: the
  * files, each memory (ports, mask granularity, read latency, every instance's path) and each
  * black box (what it is, every instance). */
object EmitFiles {
  /** One memory module: `depth` words of `width` bits, its ports, the bits each write-mask bit
    * covers (None: no mask), and the hierarchical path of each instance from the top. Reads are
    * registered: data one cycle after the address. */
  final case class Memory(module: String, depth: Long, width: Int, readPorts: Int, writePorts: Int, readWritePorts: Int,
                          maskGranularity: Option[Int], instances: Seq[String]) {
    /** The `--repl-seq-mem` configuration line. */
    def confLine: String = {
      val masked = maskGranularity.isDefined
      val ports = Seq.fill(writePorts)(if (masked) "mwrite" else "write") ++ Seq.fill(readPorts)("read") ++
        Seq.fill(readWritePorts)(if (masked) "mrw" else "rw")
      s"name $module depth $depth width $width ports ${ports.mkString(",")}" + maskGranularity.fold("")(g => s" mask_gran $g")
    }
    def bits: Long = depth * width
  }

  /** One black box: its module, what it is (the comment its source starts with) and its instances. */
  final case class BlackBox(module: String, description: String, instances: Seq[String])

  /** A module's text (with the comments just before it) and where it belongs. */
  private final case class Block(name: Option[String], text: String)

  private val moduleStart = """^module\s+(\w+)""".r.unanchored
  private val blackBoxMarker = "// ----- 8< ----- FILE"
  private val memoryArray = """(?m)^\s*reg\s+(?:\[(\d+):0\]\s*)?Memory\s*\[0:(\d+)\];""".r
  private val instRe = """(?m)^\s+(\w+)\s+(\w+)\s*\(""".r

  /** `sv` cut into blocks: each module with the comment lines before it; text outside modules
    * stays in a block of no name. Black-box sources after firtool's file markers are flagged. */
  private def blocks(sv: String): (Seq[Block], Set[String]) = {
    val out = Seq.newBuilder[Block]
    val pending = new StringBuilder
    var current: Option[String] = None
    var inBlackBoxes = false
    val boxes = Set.newBuilder[String]
    for (line <- sv.linesWithSeparators) {
      if (line.startsWith(blackBoxMarker)) inBlackBoxes = true
      current match {
        case None =>
          moduleStart.findPrefixMatchOf(line).map(_.group(1)) match {
            case Some(m) => current = Some(m); if (inBlackBoxes) boxes += m; pending ++= line
            case None if line.trim.isEmpty || line.trim.startsWith("//") => pending ++= line
            case None => out += Block(None, pending.toString + line); pending.clear()
          }
        case Some(m) =>
          pending ++= line
          if (line.trim.startsWith("endmodule")) { out += Block(Some(m), pending.toString); pending.clear(); current = None }
      }
    }
    if (pending.nonEmpty) out += Block(None, pending.toString)
    (out.result(), boxes.result())
  }

  /** Every instance path of every module under `top`, by module. */
  private def instances(bodies: Map[String, String], top: String): Map[String, Seq[String]] = {
    val paths = scala.collection.mutable.LinkedHashMap.empty[String, Vector[String]]
    def walk(module: String, path: String): Unit =
      for (m <- instRe.findAllMatchIn(bodies(module)) if bodies.contains(m.group(1)) && m.group(1) != module) {
        val p = s"$path.${m.group(2)}"
        paths(m.group(1)) = paths.getOrElse(m.group(1), Vector.empty) :+ p
        walk(m.group(1), p)
      }
    walk(top, top)
    paths.toMap
  }

  /** The design `top` in firtool's SystemVerilog `sv`, read once: its modules, memories, black
    * boxes and their instances. */
  def read(sv: String, top: String): Design = new Design(sv, top)

  final class Design(sv: String, top: String) {
    private val (bs, boxes) = blocks(sv)
    private val inst = instances(bs.collect { case Block(Some(n), t) => n -> t }.toMap, top)

    /** The memories (firtool's memory modules), by module name. */
    val memories: Seq[Memory] =
      bs.collect { case Block(Some(n), t) if memoryArray.findFirstIn(t).isDefined => n -> t }.map { case (n, t) =>
        val arr = memoryArray.findFirstMatchIn(t).get
        val width = Option(arr.group(1)).fold(1)(_.toInt + 1)
        def count(prefix: String) = s"""\\b$prefix(\\d+)_addr\\b""".r.findAllMatchIn(t).map(_.group(1)).toSet.size
        val mask = """\[(\d+):0\]\s+W0_mask""".r.findFirstMatchIn(t).map(_.group(1).toInt + 1)
          .orElse(if ("""\bW0_mask\b""".r.findFirstIn(t).isDefined) Some(1) else None)
        Memory(n, arr.group(2).toLong + 1, width, count("R"), count("W"), count("RW"), mask.map(width / _), inst.getOrElse(n, Seq.empty))
      }

    /** The black boxes `top` instantiates, with the comment their source starts with. */
    val blackBoxes: Seq[BlackBox] = bs.collect { case Block(Some(n), t) if boxes(n) =>
      val comment = t.linesIterator.map(_.trim).takeWhile(!_.startsWith("module")).filter(_.startsWith("//"))
        .filterNot(l => l.startsWith(blackBoxMarker) || l.startsWith("// Generated by")).map(_.stripPrefix("//").trim).mkString(" ")
      BlackBox(n, comment, inst.getOrElse(n, Seq.empty))
    }

    /** Writes the design into `dir` as the files above; returns them, the file list first. */
    def write(dir: Path): Seq[Path] = {
      val mems = memories
      val memNames = mems.map(_.module).toSet
      def text(keep: Block => Boolean) = bs.filter(keep).map(_.text).mkString
      val design = text(b => b.name.forall(n => !memNames(n) && !boxes(n)))
      val files = Seq(s"${top}_blackboxes.sv" -> text(_.name.exists(boxes)), s"${top}_memories.sv" -> text(_.name.exists(memNames)),
        s"$top.sv" -> design)
      Files.createDirectories(dir)
      val written = files.map { case (f, t) => Files.write(dir.resolve(f), t.getBytes(UTF_8)) }
      val list = Files.write(dir.resolve(s"$top.f"), written.map(_.getFileName.toString).mkString("", "\n", "\n").getBytes(UTF_8))
      val conf = Files.write(dir.resolve(s"${top}_memories.conf"), mems.map(_.confLine).mkString("", "\n", "\n").getBytes(UTF_8))
      val manifest = ujson.Obj(
        "top" -> top,
        "files" -> ujson.Arr.from(written.map(f => ujson.Str(f.getFileName.toString))),
        "memories" -> ujson.Arr.from(mems.map(m => ujson.Obj("module" -> m.module, "depth" -> m.depth.toDouble, "width" -> m.width,
          "readPorts" -> m.readPorts, "writePorts" -> m.writePorts, "readWritePorts" -> m.readWritePorts,
          "maskGranularity" -> m.maskGranularity.fold[ujson.Value](ujson.Null)(ujson.Num(_)), "readLatency" -> 1,
          "instances" -> ujson.Arr.from(m.instances.map(ujson.Str(_)))))),
        "blackBoxes" -> ujson.Arr.from(blackBoxes.map(b => ujson.Obj("module" -> b.module, "description" -> b.description,
          "instances" -> ujson.Arr.from(b.instances.map(ujson.Str(_)))))))
      val json = Files.write(dir.resolve(s"${top}_manifest.json"), ujson.write(manifest, indent = 2).getBytes(UTF_8))
      list +: (written ++ Seq(conf, json))
    }
  }
}
