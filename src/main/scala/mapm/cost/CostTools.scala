package mapm.cost

import java.nio.file.{Files, Path, Paths}
import mapm.MapmError
import scala.sys.process._

/** The external programs of the cost flow: yosys (a Python with PyPI's pyosys), OpenSTA and the
  * OSU 0.18 um Liberty file. `tools/setup.sh` installs them on first use (function
  * `mapm_ensure_cost_tools`); this object asks it once per process for their paths.
  *
  * The repository root comes from the system property `mapm.root` (set by `tools/mapm` and by the
  * sbt build), else the working directory.
  */
object CostTools {
  final case class Paths3(yosysPython: Path, sta: Path, osu018Lib: Path)

  /** The repository root: where `tools/setup.sh` lives. */
  def root: Path = Paths.get(sys.props.getOrElse("mapm.root", ".")).toAbsolutePath.normalize

  private lazy val found: Either[String, Paths3] = {
    val setup = root.resolve("tools/setup.sh")
    if (!Files.isRegularFile(setup)) Left(s"cannot find $setup to install the cost tools (run from the repository root)")
    else {
      val out = new StringBuilder
      val err = new StringBuilder
      val rc = Process(Seq("bash", "-c", s"""source "$setup" && mapm_ensure_cost_tools""")).!(
        ProcessLogger(l => out.append(l).append('\n'), l => { err.append(l).append('\n'); System.err.println(l) }))
      val kv = out.toString.linesIterator.flatMap { l =>
        l.split("=", 2) match { case Array(k, v) => Some(k -> v); case _ => None }
      }.toMap
      if (rc != 0 || Seq("yosys_python", "sta", "osu018_lib").exists(k => !kv.contains(k)))
        Left(err.toString.linesIterator.toSeq.lastOption.getOrElse("cost tools could not be installed")
          .stripPrefix("mapm setup: "))
      else Right(Paths3(Paths.get(kv("yosys_python")), Paths.get(kv("sta")), Paths.get(kv("osu018_lib"))))
    }
  }

  /** The tools, installing them when missing; a [[MapmError]] with the reason when that fails. */
  def get: Paths3 = found.fold(msg => MapmError.fail(msg), identity)

  /** Whether the tools are there (installing them if they can be): for tests that cancel without. */
  def available: Either[String, Paths3] = found
}
