package mapm.model

import mapm.numerics._

/** Wall-clock seconds of each stage of [[Frame.prepare]] and of the search-and-shade run. */
final case class StageTimes(stages: Seq[(String, Double)]) {
  def +(stage: (String, Double)): StageTimes = StageTimes(stages :+ stage)
  def total: Double = stages.map(_._2).sum
}

/** Everything one frame needs before tree search and shading: the scene's photons, its query
  * points, the chosen h, the photon map and query set quantized to the accelerator's format, and
  * the direct light of the viewable image (which the accelerator does not compute).
  *
  * @param config       the scene file as loaded
  * @param format       the accelerator's number format
  * @param photons      photons as traced
  * @param emittedPaths photon paths traced (the divisor of photon power)
  * @param queries      final-gather query points, in pixel order
  * @param h            the kernel radius chosen (before quantization)
  * @param map          the photon map quantized to `format`
  * @param querySet     the query points quantized to `format`
  * @param direct       direct radiance per pixel (row-major)
  * @param times        seconds per preparation stage
  */
final case class Frame(
    config: SceneConfig,
    format: FloatFormat,
    photons: Array[Photon],
    emittedPaths: Long,
    queries: QueryPoints,
    h: Double,
    map: PhotonMap,
    querySet: QuerySet,
    direct: Array[Vec3],
    times: StageTimes
) {
  def width: Int = config.width
  def height: Int = config.height
  def pixels: Int = config.width * config.height
}

object Frame {
  private def timed[T](name: String, acc: scala.collection.mutable.ArrayBuffer[(String, Double)])(body: => T): T = {
    val t0 = System.nanoTime()
    val r = body
    acc += name -> (System.nanoTime() - t0) / 1e9
    r
  }

  /** Runs the scene side of the model: triangle KD-tree, photon tracing, primary rays, final
    * gather, direct light, the photon KD-tree, the choice of h (on that tree), and quantization to
    * `format`. The long stages draw progress bars ([[Progress]]). */
  def prepare(config: SceneConfig, format: FloatFormat, threads: Int = Parallel.defaultThreads): Frame = {
    val t = scala.collection.mutable.ArrayBuffer.empty[(String, Double)]
    val tree = timed("triangle kd-tree", t)(TriKdTree.build(config.scene))
    val traced = timed("photon tracing", t)(PhotonTracer.trace(tree, config.pointLights, config.photons,
      config.maxBounces, config.seed, threads, Some("photon tracing")))
    val primary = timed("primary rays", t)(PrimaryHits.trace(tree, config.camera, config.width, config.height, threads))
    val queries = timed("final gather", t)(
      FinalGather.gather(tree, primary, config.finalGatherRays, config.seed, threads, Some("final gather")))
    val direct = timed("direct light", t)(
      DirectLight.render(tree, primary, config.pointLights, config.directLightSamples, config.seed, threads))
    val box = config.scene.bounds
    val photonTree = timed("photon kd-tree", t)(PhotonTree.build(traced.photons, box, Some("photon kd-tree")))
    val h = timed("choose h", t)(config.h match {
      case KernelRadius.Fixed(v) => v
      case KernelRadius.Auto(k)  => KernelRadiusChooser.choose(photonTree, queries, k, 2048, Some("choose h"))
    })
    val map = timed("quantize photons", t)(PhotonMap.fromTree(photonTree, traced.photons, format, h, Some("quantize photons")))
    val qs = timed("quantize queries", t)(QuerySet.build(queries, format, Some("quantize queries")))
    Frame(config, format, traced.photons, traced.emittedPaths, queries, h, map, qs, direct, StageTimes(t.toSeq))
  }
}
