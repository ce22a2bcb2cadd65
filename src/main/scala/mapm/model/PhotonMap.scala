package mapm.model

import mapm.numerics._

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
  def fromTree(tree: PhotonTree, photons: Array[Photon], format: FloatFormat, h: Double): PhotonMap =
    fromTree(tree, photons, format, h, None)

  /** [[fromTree]] with a progress bar over the photons labelled `progress` when given. */
  def fromTree(tree: PhotonTree, photons: Array[Photon], format: FloatFormat, h: Double, progress: Option[String]): PhotonMap = {
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
    val px = new Array[Long](n); val py = new Array[Long](n); val pz = new Array[Long](n)
    val power = Array.fill(3)(new Array[Long](n))
    val split = new Array[Long](n)
    val splitValue = new Array[Double](n)
    val codec = new FormatBits(format)
    val chunk = 1 << 16
    Progress.maybe(progress, n.toLong) { bar =>
      var i = 0
      while (i < n) {
        val k = tree.photon(i)
        // encodeOr on the common path; encode only to report a value the format cannot carry
        var b = format.encodeOr(tree.x(i), -1L); px(i) = if (b != -1L) b else format.encode(tree.x(i), s"photon $k x coordinate")
        b = format.encodeOr(tree.y(i), -1L); py(i) = if (b != -1L) b else format.encode(tree.y(i), s"photon $k y coordinate")
        b = format.encodeOr(tree.z(i), -1L); pz(i) = if (b != -1L) b else format.encode(tree.z(i), s"photon $k z coordinate")
        val pw = photons(k).power
        var c = 0
        while (c < 3) {
          val v = pw(c)
          if (v.isNaN || v < 0) MapmError.fail(s"photon $k: power $pw must be non-negative")
          b = format.encodeOr(v, -1L)
          power(c)(i) = if (b != -1L) b else format.encode(v, s"photon $k power")
          c += 1
        }
        split(i) = tree.axis(i) match { case 0 => px(i); case 1 => py(i); case _ => pz(i) }
        splitValue(i) = codec.toDouble(split(i))
        i += 1
        if ((i & (chunk - 1)) == 0) bar.foreach(_.advance(chunk.toLong))
      }
      bar.foreach(_.advance((n & (chunk - 1)).toLong))
    }
    val search = new SearchTree(tree.nodeWords, splitValue)
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
  private val codec = new FormatBits(format)

  /** The same queries in `order` (a permutation of their indices): query k of the result is query
    * `order(k)` of this set. */
  def permuted(order: Array[Int]): QuerySet = {
    MapmError.check(order.length == size && order.sorted.sameElements(0 until size), "query order must be a permutation of the queries")
    new QuerySet(format, order.map(qx), order.map(qy), order.map(qz), contribution.map(c => order.map(c)), order.map(pixel))
  }
  val x: Array[Double] = qx.map(codec.toDouble)
  val y: Array[Double] = qy.map(codec.toDouble)
  val z: Array[Double] = qz.map(codec.toDouble)
}

object QuerySet {
  /** Quantizes `queries` to `format`. Positions must be finite, contributions finite and
    * non-negative, pixels non-negative (a [[MapmError]] otherwise). */
  def build(queries: Array[QueryPoint], format: FloatFormat): QuerySet = build(QueryPoints.of(queries), format, None)

  /** [[build]] from the compact [[QueryPoints]]; `progress` labels a progress bar when given. */
  def build(queries: QueryPoints, format: FloatFormat, progress: Option[String]): QuerySet = {
    val n = queries.length
    val qx = new Array[Long](n); val qy = new Array[Long](n); val qz = new Array[Long](n)
    val contribution = Array.fill(3)(new Array[Long](n))
    val pixel = new Array[Int](n)
    val bar = progress.map(new Progress(_, n.toLong))
    val chunk = 1 << 16
    val xs = queries.x; val ys = queries.y; val zs = queries.z
    val cs = Array(queries.cr, queries.cg, queries.cb)
    try {
      var i = 0
      while (i < n) {
        // encodeOr on the common path; encode only to report a value the format cannot carry
        var b = format.encodeOr(xs(i), -1L); qx(i) = if (b != -1L) b else format.encode(xs(i), s"query $i x coordinate")
        b = format.encodeOr(ys(i), -1L); qy(i) = if (b != -1L) b else format.encode(ys(i), s"query $i y coordinate")
        b = format.encodeOr(zs(i), -1L); qz(i) = if (b != -1L) b else format.encode(zs(i), s"query $i z coordinate")
        var c = 0
        while (c < 3) {
          val v = cs(c)(i)
          if (v.isNaN || v < 0) MapmError.fail(s"query $i: contribution ${queries.contribution(i)} must be non-negative")
          b = format.encodeOr(v, -1L)
          contribution(c)(i) = if (b != -1L) b else format.encode(v, s"query $i contribution")
          c += 1
        }
        if (queries.pixel(i) < 0) MapmError.fail(s"query $i: pixel index ${queries.pixel(i)} is negative")
        pixel(i) = queries.pixel(i)
        i += 1
        if ((i & (chunk - 1)) == 0) bar.foreach(_.advance(chunk.toLong))
      }
      bar.foreach(_.advance((n & (chunk - 1)).toLong))
    } finally bar.foreach(_.finish())
    new QuerySet(format, qx, qy, qz, contribution, pixel)
  }
}
