package mapm.sim

import java.nio.charset.StandardCharsets.UTF_8
import java.nio.file.{Files, Path}

import mapm.params.MapmParams
import mapm.top.Mapm
import scala.jdk.CollectionConverters._

/** The emitted SystemVerilog of a whole MAPM, cached per configuration in the [[BuildCache]]
  * (kind `emit`); the key covers the parameters, the hardware sources (everything under
  * src/main/scala/mapm except the renderer and the host-side code) and the Chisel and firtool
  * versions, so a changed generator re-emits. Beside the Verilog it writes `mapm_config.h` ([[HarnessHeader]]). */
object MapmRtl {
  def topName(p: MapmParams): String = if (p.sim.coproc) s"MapmCoproc_${p.name}" else s"Mapm_${p.name}"

  /** A hash of the hardware generator sources (everything under src/main/scala/mapm but the renderer, the command line, the simulation code and the host-side pipelines, cost orchestration and evaluation). */
  def hardwareSourceHash: String = {
    val src = Harness.root.resolve("src/main/scala/mapm")
    val skip = Set("model", "cli", "sim", "pipeline", "costflow", "evaluation").map(src.resolve)
    val files = Files.walk(src).iterator.asScala
      .filter(f => Files.isRegularFile(f) && f.toString.endsWith(".scala") && !skip.exists(f.startsWith)).toSeq.sortBy(_.toString)
    Verilator.hash(files.map(f => src.relativize(f).toString + new String(Files.readAllBytes(f), UTF_8)): _*)
  }

  /** The directory of `p`'s emitted SystemVerilog (emitting it on a cache miss, into place in one
    * step: [[AtomicDir]]) and its top module. */
  def emit(p: MapmParams, log: String => Unit = _ => ()): (Path, String) = {
    val top = topName(p)
    val dir = BuildCache.entry("emit", top, Seq(p.toString, hardwareSourceHash), d => Files.isRegularFile(d.resolve(s"$top.sv"))) { tmp =>
      log(s"emitting $top ...")
      val t0 = System.nanoTime()
      if (p.sim.coproc) {
        Emit.toFile(new mapm.soc.MapmCoproc(p), tmp, s"$top.sv")
        Files.write(tmp.resolve("mapm_config.h"), CoprocHarnessHeader(p, top).getBytes(UTF_8))
      } else {
        Emit.toFile(new Mapm(p), tmp, s"$top.sv")
        Files.write(tmp.resolve("mapm_config.h"), HarnessHeader(p).getBytes(UTF_8))
      }
      log(f"emitted in ${(System.nanoTime() - t0) / 1e9}%.1f s")
    }
    (dir, top)
  }
}
