package mapm.cost

import java.nio.file.{Files, Path}
import mapm.MapmError
import scala.sys.process._

/** Logic synthesis of one design to the cells of a Liberty library by yosys:
  * `tools/cost/synth.py`, run in its own process with the pyosys Python of [[CostTools]], in the
  * shape of OpenROAD-flow-scripts' script (generic `synth`, `dfflibmap`, `abc -D <target>` with
  * the Liberty file, `setundef -zero`, `splitnets`, `opt_clean -purge`, tie cells, `insbuf`).
  *
  * Generic synthesis runs once; each ABC script then maps its own copy in parallel: yosys' own
  * delay-driven mapping (`plain`), and one that also buffers wide fan-outs and sizes gates
  * (`buffer`). The cost flow keeps the netlist with the higher fmax.
  */
object Synthesis {
  /** The ABC scripts tools/cost/synth.py knows. */
  val AbcScripts: Seq[String] = Seq("plain", "buffer")

  /** One mapped netlist: Verilog for OpenSTA, yosys JSON for the gate-level simulator. */
  final case class Result(top: String, abc: String, delayPs: Int, dir: Path) {
    def verilog: Path = dir.resolve("netlist.v")
    def json: Path = dir.resolve("netlist.json")
    def statText: String = new String(Files.readAllBytes(dir.resolve("stat.txt")), "UTF-8")
    /** The chip area of module `module` by yosys' `stat -liberty`, for cross-checks. */
    def yosysArea(module: String = top): Option[Double] =
      ("""Chip area for (?:top )?module '\\?""" + java.util.regex.Pattern.quote(module) + """': ([0-9.eE+-]+)""").r
        .findFirstMatchIn(statText).map(_.group(1).toDouble)
  }

  /** Synthesizes `top` from `verilog` into `out/<script>/` for each ABC script in `scripts`,
    * targeting a `delayPs` clock period. `flatten` flattens the hierarchy; otherwise the `keep`
    * modules and the top stay modules and everything else is flattened into them (all modules stay
    * when `keep` is empty); `blackbox` modules are kept as black boxes (the caches' SRAM arrays).
    * Progress lines go to stderr. Returns the netlists and the wall seconds. */
  def run(verilog: Seq[Path], top: String, lib: Path, delayPs: Int, scripts: Seq[String], out: Path,
          flatten: Boolean = true, blackbox: Seq[String] = Seq.empty, keep: Seq[String] = Seq.empty): (Seq[Result], Double) = {
    MapmError.check(scripts.nonEmpty && scripts.forall(AbcScripts.contains),
      s"cost: unknown ABC script in '${scripts.mkString(",")}' (${AbcScripts.mkString(", ")})")
    MapmError.check(delayPs > 0, s"cost: synthesis delay target must be positive, got $delayPs ps")
    MapmError.check(Files.isRegularFile(lib), s"cost: Liberty file $lib not found")
    val script = CostTools.root.resolve("tools/cost/synth.py")
    MapmError.check(Files.isRegularFile(script), s"cost: $script not found (run from the repository root)")
    Files.createDirectories(out)
    val cmd = Seq(CostTools.get.yosysPython.toString, script.toString, "--verilog") ++ verilog.map(_.toAbsolutePath.toString) ++
      Seq("--top", top, "--lib", lib.toAbsolutePath.toString, "--delay-ps", delayPs.toString, "--abc", scripts.mkString(","),
        "--out", out.toAbsolutePath.toString) ++
      (if (flatten) Seq("--flatten") else Seq.empty) ++ (if (blackbox.nonEmpty) "--blackbox" +: blackbox else Seq.empty) ++
      (if (keep.nonEmpty) "--keep" +: keep else Seq.empty)
    val log = out.resolve("yosys.log")
    val t0 = System.nanoTime()
    val errs = new StringBuilder
    val rc = Process(cmd).#>(log.toFile).!(ProcessLogger(_ => (), l =>
      if (l.startsWith("mapm: ")) { if (errs.isEmpty) errs.append(l.stripPrefix("mapm: ")) } else System.err.println(l)))
    if (rc != 0) {
      // The output folder may be a build's temporary one, removed on failure: the log is kept apart.
      val kept = scala.util.Try {
        val k = Files.createTempFile(s"mapm-yosys-$top-", ".log")
        Files.copy(log, k, java.nio.file.StandardCopyOption.REPLACE_EXISTING)
        k
      }.getOrElse(log)
      MapmError.fail(if (errs.nonEmpty) errs.toString else s"yosys failed on $top (exit $rc; log kept in $kept)")
    }
    (scripts.map(s => Result(top, s, delayPs, out.resolve(s))), (System.nanoTime() - t0) / 1e9)
  }
}
