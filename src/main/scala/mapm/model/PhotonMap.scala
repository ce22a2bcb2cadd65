package mapm.model

import mapm.MapmError

/** The photon map as the hardware sees it: the KD-tree plus every per-photon value quantized to a
  * float format, all in node order (node i holds photon `tree.photon(i)`).
  *
  * @param h       kernel radius (bits)
  * @param px      photon positions (bits), likewise `py`, `pz`
  * @param power   photon power per channel (bits): power(0) red, (1) green, (2) blue
  * @param kernel  per-photon kernel value (bits), [[Shading.kernel]] of the quantized h
  * @param brdf    per-photon BRDF value (bits), [[Shading.brdf]]
  * @param split   split value per node (bits): the node photon's coordinate on the split axis
  * @param search  the search structure: node words and split values as exact doubles
  */
final class PhotonMap private (
    val format: FloatFormat,
    val tree: PhotonTree,
    val h: Long,
    val px: Array[Long],
    val py: Array[Long],
    val pz: Array[Long],
    val power: Array[Array[Long]],
    val kernel: Array[Long],
    val brdf: Array[Long],
    val split: Array[Long],
    val search: SearchTree
) {
  def size: Int = tree.size
  /** The exact value of h. */
  val hValue: Double = format.decode(h)
}

object PhotonMap {
  /** Builds the tree over `photons` in `box` and quantizes everything to `format`. */
  def build(photons: Array[Photon], box: Box, format: FloatFormat, h: Double): PhotonMap =
    fromTree(PhotonTree.build(photons, box), photons, format, h)

  /** Quantizes `tree` (built over `photons`) to `format` with kernel radius `h`.
    * h must be finite and positive, and h, h^2 and the kernel 1/(pi h) must be normal numbers of
    * the format; powers must be finite and non-negative (a [[MapmError]] otherwise). */
  def fromTree(tree: PhotonTree, photons: Array[Photon], format: FloatFormat, h: Double): PhotonMap = {
    MapmError.check(tree.size == photons.length, s"photon map: tree has ${tree.size} nodes for ${photons.length} photons")
    MapmError.check(!h.isNaN && !h.isInfinite && h > 0, s"kernel radius h = $h must be finite and positive")
    val hBits = format.encode(h, s"kernel radius h")
    val hq = format.decode(hBits)
    MapmError.check(hq > 0, s"kernel radius h = $h is below the smallest normal number of format $format")
    MapmError.check(format.tryEncode(hq * hq).isDefined, s"kernel radius h = $h: h^2 overflows format $format")
    val kernelBits = format.encode(Shading.kernel(hq), s"kernel 1/(pi h) for h = $h")
    MapmError.check(!format.isZero(kernelBits), s"kernel 1/(pi h) for h = $h is below the smallest normal number of format $format")
    val brdfBits = format.encode(Shading.brdf, "BRDF 1/pi")
    val n = tree.size
    def coord(c: Array[Double], axisName: String): Array[Long] =
      Array.tabulate(n)(i => format.encode(c(i), s"photon ${tree.photon(i)} $axisName coordinate"))
    val px = coord(tree.x, "x"); val py = coord(tree.y, "y"); val pz = coord(tree.z, "z")
    val power = Array.tabulate(3) { c =>
      Array.tabulate(n) { i =>
        val k = tree.photon(i)
        val v = photons(k).power(c)
        MapmError.check(!v.isNaN && v >= 0, s"photon $k: power ${photons(k).power} must be non-negative")
        format.encode(v, s"photon $k power")
      }
    }
    val split = Array.tabulate(n) { i => tree.axis(i) match { case 0 => px(i); case 1 => py(i); case _ => pz(i) } }
    val search = new SearchTree(NodeWord.all(tree), split.map(format.decode))
    new PhotonMap(format, tree, hBits, px, py, pz, power, Array.fill(n)(kernelBits), Array.fill(n)(brdfBits), split, search)
  }
}

/** Query points quantized to a float format, in query order (the order the host issues them).
  *
  * @param qx           positions (bits), likewise `qy`, `qz`; `x`, `y`, `z` are their exact values
  * @param contribution contribution per channel (bits): (0) red, (1) green, (2) blue
  * @param pixel        image pixel each query contributes to
  */
final class QuerySet private (
    val format: FloatFormat,
    val qx: Array[Long],
    val qy: Array[Long],
    val qz: Array[Long],
    val contribution: Array[Array[Long]],
    val pixel: Array[Int]
) {
  def size: Int = pixel.length
  val x: Array[Double] = qx.map(format.decode)
  val y: Array[Double] = qy.map(format.decode)
  val z: Array[Double] = qz.map(format.decode)
}

object QuerySet {
  /** Quantizes `queries` to `format`. Positions must be finite, contributions finite and
    * non-negative, pixels non-negative (a [[MapmError]] otherwise). */
  def build(queries: Array[QueryPoint], format: FloatFormat): QuerySet = {
    val n = queries.length
    def coord(axis: Int, name: String): Array[Long] =
      Array.tabulate(n)(i => format.encode(queries(i).position(axis), s"query $i $name coordinate"))
    val contribution = Array.tabulate(3) { c =>
      Array.tabulate(n) { i =>
        val v = queries(i).contribution(c)
        MapmError.check(!v.isNaN && v >= 0, s"query $i: contribution ${queries(i).contribution} must be non-negative")
        format.encode(v, s"query $i contribution")
      }
    }
    val pixel = Array.tabulate(n) { i =>
      MapmError.check(queries(i).pixel >= 0, s"query $i: pixel index ${queries(i).pixel} is negative")
      queries(i).pixel
    }
    new QuerySet(format, coord(0, "x"), coord(1, "y"), coord(2, "z"), contribution, pixel)
  }
}
