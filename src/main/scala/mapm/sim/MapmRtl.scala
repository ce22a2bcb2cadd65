package mapm.sim

import java.nio.charset.StandardCharsets.UTF_8
import java.nio.file.{Files, Path}

import mapm.params.MapmParams
import mapm.top.Mapm
import scala.jdk.CollectionConverters._

/** The emitted SystemVerilog of a whole MAPM, cached per configuration under
  * `target/emit/<Mapm_name>-<hash>/`; the hash covers the parameters and the hardware sources
  * (everything under src/main/scala/mapm except the model, CLI and simulation code), so a
  * changed generator re-emits. Beside the Verilog it writes `mapm_config.h` ([[HarnessHeader]]). */
object MapmRtl {
  def topName(p: MapmParams): String = s"Mapm_${p.name}"

  private def hardwareSourceHash: String = {
    val src = Harness.root.resolve("src/main/scala/mapm")
    val skip = Set("model", "cli", "sim").map(src.resolve)
    val files = Files.walk(src).iterator.asScala
      .filter(f => Files.isRegularFile(f) && f.toString.endsWith(".scala") && !skip.exists(f.startsWith)).toSeq.sortBy(_.toString)
    Verilator.hash(files.map(f => src.relativize(f).toString + new String(Files.readAllBytes(f), UTF_8)): _*)
  }

  /** The directory of `p`'s emitted SystemVerilog (emitting it on a cache miss) and its top module. */
  def emit(p: MapmParams, log: String => Unit = _ => ()): (Path, String) = {
    val top = topName(p)
    val dir = Harness.root.resolve("target/emit").resolve(s"$top-${Verilator.hash(p.toString, hardwareSourceHash)}")
    val stamp = dir.resolve(".complete")
    if (!Files.isRegularFile(stamp)) {
      log(s"emitting $top ...")
      val t0 = System.nanoTime()
      Emit.toFile(new Mapm(p), dir, s"$top.sv")
      Files.write(dir.resolve("mapm_config.h"), HarnessHeader(p).getBytes(UTF_8))
      Files.write(stamp, Array.emptyByteArray)
      log(f"emitted in ${(System.nanoTime() - t0) / 1e9}%.1f s")
    }
    (dir, top)
  }
}
