package mapm.sim

import mapm.MapmError
import mapm.format.{MemoryImage, SlotLayout}
import mapm.model.{PhotonMap, QuerySet}

/** The memory image ([[MemoryImage]], docs/memory-layout.md) of a frame the model prepared: its
  * photon map's tree and photons and its query points, in the records of `layout`. */
object FrameImage {
  /** The image of a photon map and its queries; the stream issues the queries in `order`
    * (default: query order). */
  def of(map: PhotonMap, queries: QuerySet, layout: SlotLayout = SlotLayout.Packed, order: Option[Array[Int]] = None): MemoryImage = {
    MapmError.check(map.format == queries.format, s"memory image: photon map (${map.format}) and queries (${queries.format}) use different formats")
    val stream = order.getOrElse(Array.tabulate(queries.size)(identity))
    MapmError.check(stream.sorted.sameElements(0 until queries.size), "memory image: the stream order must be a permutation of the queries")
    new MemoryImage(map.format, layout, map.h, map.split.clone(), map.tree.nodeWords,
      Array(map.px, map.py, map.pz, map.power(0), map.power(1), map.power(2), map.kernel, map.brdf).map(_.clone()),
      queries.contribution.map(_.clone()), queries.pixel.clone(), Array(queries.qx, queries.qy, queries.qz).map(_.clone()), stream.clone())
  }
}
