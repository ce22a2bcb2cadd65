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

  /** The most TSMs and SOMs together of a whole MAPM this generator emits. The parameters address
    * up to 1024 of each ([[mapm.params.ModuleCounts]]), but firtool's time grows faster than the
    * design: on the 2-core, 24 GB machine 256/256/4 emits in about 6 minutes at 2.4 GB (docs/mapm.md,
    * "Elaboration"), 512/512/4 in 27 (2.5 GB), and 1024/1024/4 did not finish in 18. */
  val MaxEmitModules = 512

  /** A one-line [[mapm.MapmError]] when `p` is beyond [[MaxEmitModules]], unless `beyondLimit`. */
  def checkEmittable(p: MapmParams, beyondLimit: Boolean = false): Unit = {
    val n = p.counts.tsm + p.counts.som
    mapm.MapmError.check(beyondLimit || n <= MaxEmitModules,
      s"${p.counts.label} has $n TSMs and SOMs together; whole MAPMs are emitted up to $MaxEmitModules (256/256/4 takes about 6 min " +
        s"and 2.4 GB on a 2-core machine, 512/512/4 about 27 min, 1024/1024/4 did not finish in 18 min): a smaller configuration, " +
        "the units alone (emit-soa, emit-tsa), or `emit --beyond-limit` to try")
  }

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
    checkEmittable(p)
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
