package mapm.evaluation

import java.nio.file.{Files, Path, Paths}
import mapm.{MapmError, SetupScript}
import scala.sys.process._

/** NVIDIA's FLIP (Andersson et al., "FLIP: A Difference Evaluator for Alternating Images", HPG
  * 2020), the perceptual image metric of the precision study: the mean FLIP error of a test image
  * against a reference, 0 for identical images, 1 at most. LDR-FLIP on 8-bit sRGB PNGs at the
  * tool's default viewing condition (67 pixels per degree: a 0.7 m wide 4K display at 0.7 m).
  * The tool comes from PyPI (`flip-evaluator`, installed into a venv by `tools/setup.sh`'s
  * `mapm_ensure_flip` on first use). */
object Flip {
  private lazy val found: Either[String, Path] =
    SetupScript.run(mapm.cost.CostTools.root, "mapm_ensure_flip", Seq("flip"), echo = true).map(kv => Paths.get(kv("flip")))

  /** The `flip` command, installing it when missing; a [[MapmError]] with the reason when that fails. */
  def executable: Path = found.fold(msg => MapmError.fail(s"FLIP: $msg"), identity)

  /** The mean FLIP error of `test` against `reference` (PNG files of one size). */
  def meanError(reference: Path, test: Path): Double = {
    val dir = Files.createTempDirectory("mapm-flip")
    val out = new StringBuilder
    val rc = try Process(Seq(executable.toString, "-r", reference.toAbsolutePath.toString, "-t", test.toAbsolutePath.toString,
      "-v", "1", "-nerm"), dir.toFile).!(ProcessLogger(l => out.append(l).append('\n'), l => out.append(l).append('\n')))
    finally { Files.list(dir).forEach(Files.delete(_)); Files.delete(dir) }
    val mean = """(?m)^\s*Mean:\s*([0-9.eE+-]+)\s*$""".r.findFirstMatchIn(out.toString).map(_.group(1).toDouble)
    if (rc != 0 || mean.isEmpty)
      MapmError.fail(s"FLIP failed on $test against $reference: ${out.toString.linesIterator.map(_.trim).find(_.nonEmpty).getOrElse(s"exit $rc")}")
    mean.get
  }

  /** The tool's identity (its help's first line, "FLIP v1.7."), for keys of cached results. */
  lazy val version: String = Process(Seq(executable.toString, "-h")).lazyLines_!.headOption.map(_.trim).getOrElse("FLIP")
}
