package mapm.evaluation

import mapm.params.MapmParams

/** The four workloads of the dissertation's chapter 4 that `evaluate` runs, each a scene file of
  * the checkout over its table's configurations. */
object Workloads {
  /** A workload: its key, title, scene file (relative to the checkout) and configurations. */
  final case class Workload(key: String, title: String, scene: String, configs: Seq[(Int, Int, Int)])

  val quickConfigs: Seq[(Int, Int, Int)] = Seq((4, 4, 2), (16, 16, 2))

  def of(quick: Boolean): Seq[Workload] = {
    def pick(cs: Seq[(Int, Int, Int)]) = if (quick) cs.filter(quickConfigs.contains) else cs
    Seq(Workload("cornell-2k", "Cornell box, 2k photons", "test-scenes/cornell-box/scene.json", pick(MapmParams.table48Configs)),
      Workload("cornell-8k", "Cornell box, 8k photons", "test-scenes/cornell-box/scene-8k.json", pick(Dissertation.table411Configs)),
      Workload("sponza-corridor", "Sponza corridor, 8k photons", "test-scenes/sponza/corridor.json", pick(Dissertation.table411Configs)),
      Workload("sponza-atrium", "Sponza atrium, 8k photons", "test-scenes/sponza/atrium.json", pick(Dissertation.table411Configs)))
  }
}
