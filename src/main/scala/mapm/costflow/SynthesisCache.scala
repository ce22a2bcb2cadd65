package mapm.costflow

import java.nio.charset.StandardCharsets.UTF_8
import java.nio.file.{Files, Path, StandardCopyOption}

import mapm.cost.{CostTools, Synthesis}
import mapm.sim.BuildCache
import scala.jdk.CollectionConverters._
import scala.util.Try

/** [[Synthesis.run]] through the [[BuildCache]] (kind `synth`): the same Verilog synthesized with
  * the same settings (top, Liberty file, delay target, ABC scripts, kept and black-box modules) by
  * the same synth.py and tools gives the same netlists, so a unit is synthesized once per machine,
  * whichever command, spec or checkout asks first. The netlists are copied into `out` as
  * [[Synthesis.run]] writes them; the seconds returned are those synthesis took when it ran. */
object SynthesisCache {
  def run(verilog: Seq[Path], top: String, lib: Path, delayPs: Int, scripts: Seq[String], out: Path,
          flatten: Boolean = true, blackbox: Seq[String] = Seq.empty, keep: Seq[String] = Seq.empty): (Seq[Synthesis.Result], Double) = {
    val script = CostTools.root.resolve("tools/cost/synth.py")
    val inputs = verilog.map(f => new String(Files.readAllBytes(f), UTF_8)) ++ Seq(top, s"${lib.getFileName} ${Try(Files.size(lib)).getOrElse(-1L)}",
      delayPs.toString, scripts.mkString(","), s"flatten=$flatten", blackbox.mkString(","), keep.mkString(","),
      Try(new String(Files.readAllBytes(script), UTF_8)).getOrElse(""), CostTools.versions)
    var ran: Option[Double] = None
    val cached = BuildCache.entry("synth", top, inputs, d => Files.isRegularFile(d.resolve("seconds"))) { tmp =>
      val (_, secs) = Synthesis.run(verilog, top, lib, delayPs, scripts, tmp, flatten, blackbox, keep)
      Files.write(tmp.resolve("seconds"), f"$secs%.3f".getBytes(UTF_8))
      ran = Some(secs)
    }
    Files.walk(cached).iterator.asScala.filter(_ != cached).foreach { f =>
      val t = out.resolve(cached.relativize(f).toString)
      if (Files.isDirectory(f)) Files.createDirectories(t)
      else if (f.getFileName.toString != "seconds") { Files.createDirectories(t.getParent); Files.copy(f, t, StandardCopyOption.REPLACE_EXISTING) }
    }
    val secs = ran.getOrElse(Try(new String(Files.readAllBytes(cached.resolve("seconds")), UTF_8).trim.toDouble).getOrElse(0.0))
    (scripts.map(s => Synthesis.Result(top, s, delayPs, out.resolve(s))), secs)
  }
}
