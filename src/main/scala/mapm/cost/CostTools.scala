package mapm.cost

import java.nio.file.{Path, Paths}
import mapm.{MapmError, SetupScript}

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

  private lazy val found: Either[String, Paths3] =
    SetupScript.run(root, "mapm_ensure_cost_tools", Seq("yosys_python", "sta", "osu018_lib"), echo = true)
      .map(kv => Paths3(Paths.get(kv("yosys_python")), Paths.get(kv("sta")), Paths.get(kv("osu018_lib"))))

  /** The tools, installing them when missing; a [[MapmError]] with the reason when that fails. */
  def get: Paths3 = found.fold(msg => MapmError.fail(msg), identity)

  /** The tools' identities, for keys of cached results: the yosys venv (named by its pyosys
    * version), OpenSTA's `-version` and the Liberty file's size. */
  lazy val versions: String = {
    val t = get
    val sta = scala.util.Try(scala.sys.process.Process(Seq(t.sta.toString, "-version")).!!.trim).getOrElse("unknown")
    s"yosys=${t.yosysPython} sta=$sta liberty=${java.nio.file.Files.size(t.osu018Lib)}"
  }

  /** Whether the tools are there (installing them if they can be): for tests that cancel without. */
  def available: Either[String, Paths3] = found
}
