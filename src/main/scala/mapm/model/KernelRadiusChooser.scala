package mapm.model

import mapm.numerics._

import mapm.MapmError

/** Chooses the kernel radius h for `"h": {"auto": k}`: the smallest h (to a relative precision of
  * 1e-4) at which the average query point of a sample has at least `k` photons strictly closer
  * than h. The count is monotone in h, so a bisection on log h finds it; each step runs the
  * 3.1.6 tree search over the sample and counts the photons it returns that lie within h.
  *
  * The sample is up to `sampleSize` queries taken at even strides through the query array, so the
  * choice is deterministic for a given scene.
  */
object KernelRadiusChooser {
  def choose(photons: Array[Photon], box: Box, queries: Array[QueryPoint], photonsPerQuery: Double,
             sampleSize: Int = 2048): Double = {
    MapmError.check(photons.nonEmpty, "h auto: there are no photons to choose h from")
    MapmError.check(queries.nonEmpty, "h auto: there are no query points to choose h from (did every ray miss?)")
    choose(PhotonTree.build(photons, box), QueryPoints.of(queries), photonsPerQuery, sampleSize, None)
  }

  /** [[choose]] on a photon tree already built (the photon tree of 3.1.4 over the scene box,
    * which the frame builds anyway) and the compact query points. `progress` labels a progress bar
    * over the bisection steps when given. */
  def choose(tree: PhotonTree, queries: QueryPoints, photonsPerQuery: Double, sampleSize: Int,
             progress: Option[String]): Double = {
    MapmError.check(tree.size > 0, "h auto: there are no photons to choose h from")
    MapmError.check(queries.length > 0, "h auto: there are no query points to choose h from (did every ray miss?)")
    MapmError.check(photonsPerQuery > 0 && photonsPerQuery <= tree.size,
      s"h auto: target of $photonsPerQuery photons per query must be in (0, ${tree.size}] (the photon count)")
    val box = tree.box
    val search = new SearchTree(tree.nodeWords, tree.split)
    val searcher = new TreeSearcher(search)
    val n = math.min(sampleSize, queries.length)
    val sample = Array.tabulate(n)(i => queries.position((i.toLong * queries.length / n).toInt))

    def averageCount(h: Double): Double = {
      var total = 0L
      val h2 = h * h
      for (q <- sample) {
        searcher.search(q.x, q.y, q.z, h)
        var k = 0
        while (k < searcher.soCount) {
          val i = searcher.so(k)
          val dx = tree.x(i) - q.x; val dy = tree.y(i) - q.y; val dz = tree.z(i) - q.z
          if (dx * dx + dy * dy + dz * dz < h2) total += 1
          k += 1
        }
      }
      total.toDouble / n
    }

    val diagonal = math.max(box.extent.length, 1e-30)
    var lo = diagonal * 1e-9 // finds (almost surely) nothing
    var hi = diagonal * 2    // every query finds every photon
    val steps = math.ceil(math.log(math.log(hi / lo) / math.log1p(1e-4)) / math.log(2)).toLong
    Progress.maybe(progress, steps) { bar =>
      while (hi / lo > 1 + 1e-4) {
        val mid = math.sqrt(lo * hi)
        if (averageCount(mid) >= photonsPerQuery) hi = mid else lo = mid
        bar.foreach(_.advance())
      }
    }
    hi
  }
}
