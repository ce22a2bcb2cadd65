package mapm.cli

import mapm.pipeline._

import mainargs.{ParserForMethods, arg, main}
import mapm.model.Parallel
import mapm.numerics.FloatFormat
import Args.FloatFormatReader

/** `mapm model`: the software render of a scene (see [[ModelRun]]). */
object ModelCommand extends Command {
  val name = "model"
  val summary = "software render of a scene: PNG, PFM and stats JSON from the model"

  @main
  def model(
      @arg(doc = "scene description file (JSON)") scene: String = RenderCommand.defaultScene,
      @arg(doc = "number format (default: the scene's, else fp32)") format: Option[FloatFormat] = None,
      @arg(doc = "output folder") out: String = "out",
      @arg(doc = "worker threads") threads: Int = Parallel.defaultThreads,
      @arg(name = "g", doc = "guard digits of the SOA's online colour chain (0 = the dissertation's)") g: Int = 3
  ): Int = { ModelRun.run(scene, format, out, threads, g = g); 0 }

  lazy val parser: ParserForMethods[_] = ParserForMethods(this)

  def run(args: Seq[String]): Int = Args.run(this, args)
}
