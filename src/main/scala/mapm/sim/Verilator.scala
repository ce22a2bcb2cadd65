package mapm.sim

import java.nio.file.{Files, Path}
import mapm.MapmError
import scala.sys.process._

/** Finding and running Verilator for the project's own harnesses (not chiseltest's). */
object Verilator {
  /** Whether verilator is on the PATH. */
  def available: Boolean = onPath.isDefined

  private def onPath: Option[java.nio.file.Path] = sys.env.getOrElse("PATH", "").split(java.io.File.pathSeparator).iterator
    .map(d => java.nio.file.Paths.get(d, "verilator")).find(p => Files.isExecutable(p))

  /** The verilator executable, or a [[MapmError]] telling how to get it. */
  def executable: String = {
    onPath.map(_.toString).getOrElse(
      MapmError.fail("verilator not found on PATH (tools/sbt installs it; or apt-get install verilator)"))
  }

  /** Verilates `svFiles` with the C++ `harness` into an executable `dir/name` (built in
    * `dir/obj`), using ccache when present. Returns the executable; a [[MapmError]] with the
    * tail of the log when the build fails. */
  def build(svFiles: Seq[Path], harness: Path, top: String, dir: Path, name: String,
            extraFlags: Seq[String] = Seq.empty): Path = {
    val exe = dir.resolve(name)
    val obj = dir.resolve("obj")
    Files.createDirectories(obj)
    val cmd = Seq(executable, "--cc", "--exe", "--build", "-O3", "-Wno-fatal", "--x-assign", "fast",
      "--x-initial", "fast", "--top-module", top, "-Mdir", obj.toString, "-o", exe.toAbsolutePath.toString,
      "-j", Runtime.getRuntime.availableProcessors.toString, "-CFLAGS", "-O2") ++ extraFlags ++
      svFiles.map(_.toString) :+ harness.toString
    val hasCcache = sys.env.getOrElse("PATH", "").split(java.io.File.pathSeparator)
      .exists(d => Files.isExecutable(java.nio.file.Paths.get(d, "ccache")))
    val env = if (hasCcache) Seq("OBJCACHE" -> "ccache") else Seq.empty
    val log = new StringBuilder
    val rc = Process(cmd, dir.toFile, env: _*).!(ProcessLogger(l => log.append(l).append('\n'), l => log.append(l).append('\n')))
    if (rc != 0 || !Files.isExecutable(exe)) {
      val tail = log.toString.linesIterator.toSeq.takeRight(15).mkString("\n")
      MapmError.fail(s"verilator build of $top failed (exit $rc) in $dir:\n$tail")
    }
    exe
  }

  /** A short stable hash of some strings, for build-cache directory names. */
  def hash(parts: String*): String = {
    val md = java.security.MessageDigest.getInstance("SHA-256")
    parts.foreach(p => md.update(p.getBytes("UTF-8")))
    md.digest().take(8).map(b => f"${b & 0xff}%02x").mkString
  }
}
