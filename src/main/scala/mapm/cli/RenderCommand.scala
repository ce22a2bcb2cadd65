package mapm.cli

import mainargs.{ParserForMethods, arg, main}
import mapm.model.{FloatFormat, Parallel}
import Args.FloatFormatReader

/** `mapm render`: the main job, rendering a frame. Today it renders through the software model
  * (the same as `model`); with the whole-MAPM generator and its Verilator harness it runs the frame
  * through the emitted RTL and compares it against the model. */
object RenderCommand extends Command {
  val name = "render"
  val summary = "render a frame (the main job; today through the software model)"
  val defaultScene = "test-scenes/cornell-box/scene.json"

  @main
  def render(
      @arg(doc = "scene description file (JSON)") scene: String = defaultScene,
      @arg(doc = "number format: fp32, bf16, fp16, fp24 or E,M (default: the scene's, else fp32)") format: Option[FloatFormat] = None,
      @arg(doc = "output folder") out: String = "out",
      @arg(doc = "worker threads") threads: Int = Parallel.defaultThreads,
      @arg(name = "g", doc = "guard digits of the SOA's online colour chain (0 = the dissertation's)") g: Int = 3
  ): Int = { ModelRun.run(scene, format, out, threads, g = g); 0 }

  def run(args: Seq[String]): Int = Args.run(ParserForMethods(this), args, name)
}
