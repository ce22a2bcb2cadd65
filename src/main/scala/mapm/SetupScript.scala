package mapm

import java.nio.file.{Files, Path}
import scala.sys.process._

/** Asking `tools/setup.sh` for external tools: each `mapm_ensure_*` function installs what is
  * missing (apt as root, a venv for PyPI) and prints `key=value` lines naming what it found. */
object SetupScript {
  /** The executable `tool` on the PATH, if any. */
  def which(tool: String): Option[Path] = sys.env.getOrElse("PATH", "").split(java.io.File.pathSeparator).iterator
    .map(d => java.nio.file.Paths.get(d, tool)).find(Files.isExecutable(_))

  /** Runs `function` of `root/tools/setup.sh`; the `key=value` lines it printed, all of `keys`
    * among them, or Left(the script's last error line). `echo` shows its stderr as it comes. */
  def run(root: Path, function: String, keys: Seq[String], echo: Boolean = false): Either[String, Map[String, String]] = {
    val setup = root.resolve("tools/setup.sh")
    if (!Files.isRegularFile(setup)) return Left(s"cannot find $setup to install tools (run from the repository root)")
    val out = new StringBuilder
    val err = new StringBuilder
    val rc = Process(Seq("bash", "-c", s"""source "$setup" && $function""")).!(
      ProcessLogger(l => out.append(l).append('\n'), l => { err.append(l).append('\n'); if (echo) System.err.println(l) }))
    val kv = out.toString.linesIterator.flatMap { l =>
      l.split("=", 2) match { case Array(k, v) => Some(k -> v); case _ => None }
    }.toMap
    if (rc != 0 || keys.exists(k => !kv.contains(k)))
      Left(err.toString.linesIterator.toSeq.lastOption.getOrElse(s"$function could not install its tools").stripPrefix("mapm setup: "))
    else Right(kv)
  }
}
