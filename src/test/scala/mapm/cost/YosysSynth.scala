package mapm.cost

import java.nio.charset.StandardCharsets
import java.nio.file.{Files, Path}
import org.scalatest.Assertions
import scala.sys.process._

/** Synthesizes small Verilog designs to the OSU 0.18 um cells with yosys, for the tests: the
  * cost flow's script shape (the library has no tie cells, so no `hilomap`), with
  * `rename -enumerate` so the JSON and Verilog netlists name the cells alike.
  */
object YosysSynth {
  /** A synthesized design: the yosys JSON and Verilog netlists and the library. */
  final case class Result(json: Path, verilog: Path, libPath: Path) {
    /** The netlist, read back. */
    def netlist: Netlist = Netlist.read(json)
  }

  /** The cost tools, or cancels the calling test saying why they are missing. */
  def tools(): CostTools.Paths3 = CostTools.available match {
    case Right(t)  => t
    case Left(why) => Assertions.cancel(s"cost tools (yosys, OSU 0.18 um cells) unavailable: $why")
  }

  /** The library, or cancels the calling test when the tools are missing. */
  lazy val library: Liberty.Library = Liberty.read(tools().osu018Lib)

  /** Synthesizes `verilog` with top module `top`; `structural` reads the library cells first,
    * for designs that instantiate them. Fails the test with yosys's last lines on an error.
    */
  def apply(verilog: String, top: String, structural: Boolean = false): Result = {
    val t = tools()
    val dir = Files.createTempDirectory("mapm-gatesim")
    val src = dir.resolve(s"$top.v")
    Files.write(src, verilog.getBytes(StandardCharsets.UTF_8))
    val lib = t.osu018Lib.toString
    val json = dir.resolve(s"$top.json")
    val out = dir.resolve(s"${top}_netlist.v")
    val passes = (if (structural) Seq(s"read_liberty -lib $lib") else Seq.empty) ++ Seq(
      s"read_verilog -sv $src",
      s"hierarchy -top $top",
      s"synth -flatten -top $top",
      s"dfflibmap -liberty $lib",
      s"abc -D 10000 -liberty $lib",
      "opt_clean",
      "setundef -zero",
      "splitnets -ports",
      "opt_clean -purge",
      "insbuf -buf BUFX2 A Y",
      "rename -enumerate",
      s"write_json $json",
      s"write_verilog -noattr $out")
    val script = dir.resolve("synth.py")
    Files.write(script, (
      "from pyosys import libyosys as ys\n" +
        "d = ys.Design()\n" +
        passes.map(p => s"ys.run_pass(${pyString(p)}, d)\n").mkString).getBytes(StandardCharsets.UTF_8))
    val log = new StringBuilder
    val rc = Process(Seq(t.yosysPython.toString, script.toString), dir.toFile).!(ProcessLogger(l => log.append(l).append('\n')))
    if (rc != 0 || !Files.isRegularFile(json))
      Assertions.fail(s"yosys failed on $top (rc $rc):\n${log.toString.linesIterator.toSeq.takeRight(15).mkString("\n")}")
    Result(json, out, t.osu018Lib)
  }

  /** A Python string literal of `s`. */
  private def pyString(s: String): String = "'" + s.replace("\\", "\\\\").replace("'", "\\'") + "'"
}
