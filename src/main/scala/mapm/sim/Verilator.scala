package mapm.sim

import java.nio.file.{Files, Path}
import mapm.MapmError
import scala.sys.process._

/** Finding and running Verilator for the project's own harnesses (not chiseltest's). */
object Verilator {
  /** Whether verilator is on the PATH. */
  def available: Boolean = onPath.isDefined

  private def onPath: Option[java.nio.file.Path] = mapm.SetupScript.which("verilator")

  /** The verilator executable, or a [[MapmError]] telling how to get it. */
  def executable: String = {
    onPath.map(_.toString).getOrElse(
      MapmError.fail("verilator not found on PATH (tools/sbt installs it; or apt-get install verilator)"))
  }

  /** The C++ optimisation of the generated code: Verilator's defaults for the per-cycle code and
    * the run-time library (`-Os`: at 16/16/2 `-O2` ran 11 % slower, its larger code missing the
    * instruction cache in the SOAs' big per-cycle functions; docs/harness.md), and none for the
    * run-once construction code (OPT_SLOW), which only lengthens the build. Passed as a make
    * variable: Verilator 5.006 puts its OPT_* flags after the user's CFLAGS, so the `-CFLAGS -O2`
    * used before never reached the per-cycle code (still `-Os`) and only slowed the build of the
    * run-once code (the order was fixed upstream in 5.010). */
  lazy val optFlags: Seq[String] = optFlagsFor(cxxOpt)

  /** The make variables for C++ optimisation `opt` of the per-cycle code and run-time library
    * (Verilator's -Os when None); the run-once code always at -O0. */
  private def optFlagsFor(opt: Option[String]): Seq[String] = Seq("-MAKEFLAGS", "OPT_SLOW=-O0") ++
    opt.toSeq.flatMap(o => Seq("-MAKEFLAGS", s"OPT_FAST=$o", "-MAKEFLAGS", s"OPT_GLOBAL=$o"))

  /** The optimisation of whole-MAPM harness builds ([[Harness]]): `MAPM_HARNESS_CXX_OPT` when set,
    * else [[cxxOpt]]'s. The tests set -O0 for them: their frames simulate in about a second each
    * at -O1, so the build is nearly all of the time, and -O0 compiles in about 45 % less CPU
    * (docs/testing.md); the unit pipes, whose exhaustive runs simulate for minutes, keep -O1. */
  lazy val harnessOptFlags: Seq[String] = optFlagsFor(sys.env.get("MAPM_HARNESS_CXX_OPT").filter(_.nonEmpty).map(checkOpt("MAPM_HARNESS_CXX_OPT")).orElse(cxxOpt))

  private def checkOpt(variable: String)(o: String): String = {
    MapmError.check(Set("-O0", "-O1", "-O2", "-O3", "-Os")(o), s"$variable must be one of -O0, -O1, -O2, -O3, -Os; got '$o'")
    o
  }

  /** `MAPM_CXX_OPT` (-O0 to -O3 or -Os), when set: the C++ optimisation of the per-cycle code and
    * the run-time library instead of Verilator's -Os. The tests set -O1 (build.sbt): on a 4/4/2
    * build it took 41 % less compile CPU than -Os (62 s against 105 s) and simulated the test frame
    * as fast (0.48 s against 0.44 s); -O0 took 35 s but simulated 3.8 times slower (docs/testing.md). */
  lazy val cxxOpt: Option[String] = sys.env.get("MAPM_CXX_OPT").filter(_.nonEmpty).map(checkOpt("MAPM_CXX_OPT"))

  /** Verilates `svFiles` with the C++ `harness` into an executable `dir/name` (built in
    * `dir/obj`), using ccache when present and `ccache` is set. `log` gets the build's progress
    * ([[BuildProgress]]: a bar of C++ files on a terminal, else a status line every 30 s).
    * Returns the executable; a [[MapmError]] with the tail of the log when the build fails. */
  def build(svFiles: Seq[Path], harness: Path, top: String, dir: Path, name: String,
            extraFlags: Seq[String] = Seq.empty, ccache: Boolean = true, log: String => Unit = _ => (),
            opt: Seq[String] = optFlags): Path = {
    val exe = dir.resolve(name)
    val obj = dir.resolve("obj")
    Files.createDirectories(obj)
    val cmd = Seq(executable, "--cc", "--exe", "--build", "-O3", "-Wno-fatal", "--x-assign", "fast",
      "--x-initial", "fast", "--top-module", top, "-Mdir", obj.toString, "-o", exe.toAbsolutePath.toString,
      "-j", Runtime.getRuntime.availableProcessors.toString) ++ opt ++ extraFlags ++
      svFiles.map(_.toString) :+ harness.toString
    val hasCcache = ccache && mapm.SetupScript.which("ccache").isDefined
    // Paths under `dir` reach ccache relative to it, so a build in a fresh folder (AtomicDir's
    // private name) still hits the cache of an earlier one.
    val env = if (hasCcache) Seq("OBJCACHE" -> "ccache", "CCACHE_BASEDIR" -> dir.toAbsolutePath.toString, "CCACHE_NOHASHDIR" -> "1")
      else Seq("CCACHE_DISABLE" -> "1")
    val output = new StringBuilder
    val progress = new BuildProgress(top, obj, top, log)
    def take(l: String): Unit = { output.synchronized(output.append(l).append('\n')); progress.line(l) }
    val rc = try Process(cmd, dir.toFile, env: _*).!(ProcessLogger(take, take)) finally progress.close()
    if (rc != 0 || !Files.isExecutable(exe)) {
      val tail = output.toString.linesIterator.toSeq.takeRight(15).mkString("\n")
      MapmError.fail(s"verilator build of $top failed (exit $rc) in $dir:\n$tail")
    }
    exe
  }

  /** valgrind (for callgrind's instruction counts), installed through `tools/setup.sh` when
    * missing; a [[MapmError]] saying why when it cannot be. */
  lazy val valgrind: String =
    mapm.SetupScript.run(Harness.root, "mapm_ensure_valgrind", Seq("valgrind")).fold(MapmError.fail(_), _("valgrind"))

  /** A short stable hash of some strings, for build-cache directory names. */
  def hash(parts: String*): String = {
    val md = java.security.MessageDigest.getInstance("SHA-256")
    parts.foreach(p => md.update(p.getBytes("UTF-8")))
    md.digest().take(8).map(b => f"${b & 0xff}%02x").mkString
  }
}
