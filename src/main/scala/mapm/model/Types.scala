package mapm.model

import mapm.numerics._

/** A photon as photon tracing (3.1.4 step 2) leaves it, before the photon KD-tree is built.
  *
  * @param position where it landed (scene units, after the scene is moved into the positive octant)
  * @param power    RGB power it carries (watts, already divided by the number of emitted photons)
  * @param incoming unit direction it travelled along when it hit the surface
  * @param normal   unit normal of the surface it landed on, facing the incoming photon
  */
final case class Photon(position: Vec3, power: Vec3, incoming: Vec3, normal: Vec3)

/** A final-gather query point (3.1.5): the hit point of one final-gather ray.
  *
  * @param position     hit point (scene units, positive octant)
  * @param pixel        index of the image pixel it contributes to (row-major, y * width + x)
  * @param contribution RGB weight in [0,1] that scales what the photons near it return, so that the
  *                     sum over a pixel's query points is the pixel's indirect radiance
  * @param normal       unit surface normal at the hit, facing the ray
  */
final case class QueryPoint(position: Vec3, pixel: Int, contribution: Vec3, normal: Vec3)

/** Query points side by side (struct of arrays), in query order: the compact form of a frame's
  * [[QueryPoint]]s. A full-quality frame has some 15 million of them; as objects (a point and
  * three vectors each) they would be 60 million small objects that every full garbage collection
  * walks, as arrays they are ten.
  *
  * @param x     positions, likewise `y`, `z`
  * @param pixel the image pixel of each query
  * @param cr    contributions red, likewise `cg` green, `cb` blue
  * @param nx    unit normals, likewise `ny`, `nz`
  */
final class QueryPoints(
    val x: Array[Double], val y: Array[Double], val z: Array[Double],
    val pixel: Array[Int],
    val cr: Array[Double], val cg: Array[Double], val cb: Array[Double],
    val nx: Array[Double], val ny: Array[Double], val nz: Array[Double]
) {
  require(Seq(x, y, z, cr, cg, cb, nx, ny, nz).forall(_.length == pixel.length), "query point arrays of unequal length")
  def length: Int = pixel.length
  def position(i: Int): Vec3 = Vec3(x(i), y(i), z(i))
  def contribution(i: Int): Vec3 = Vec3(cr(i), cg(i), cb(i))
  /** Query point i as an object. */
  def apply(i: Int): QueryPoint = QueryPoint(position(i), pixel(i), contribution(i), Vec3(nx(i), ny(i), nz(i)))
  def toArray: Array[QueryPoint] = Array.tabulate(length)(apply)
}

object QueryPoints {
  /** The compact form of `qs`, in the same order. */
  def of(qs: Array[QueryPoint]): QueryPoints = {
    def col(f: QueryPoint => Double) = qs.map(f)
    new QueryPoints(col(_.position.x), col(_.position.y), col(_.position.z), qs.map(_.pixel),
      col(_.contribution.x), col(_.contribution.y), col(_.contribution.z), col(_.normal.x), col(_.normal.y), col(_.normal.z))
  }
}

/** Axis-aligned box. */
final case class Box(lo: Vec3, hi: Vec3) {
  def extent: Vec3 = hi - lo
  def union(o: Box): Box = Box(lo.min(o.lo), hi.max(o.hi))
  def include(p: Vec3): Box = Box(lo.min(p), hi.max(p))
  def contains(p: Vec3): Boolean =
    p.x >= lo.x && p.x <= hi.x && p.y >= lo.y && p.y <= hi.y && p.z >= lo.z && p.z <= hi.z
  def surfaceArea: Double = { val e = extent; 2 * (e.x * e.y + e.y * e.z + e.z * e.x) }
}

object Box {
  val empty: Box = Box(Vec3(Double.MaxValue, Double.MaxValue, Double.MaxValue), Vec3(-Double.MaxValue, -Double.MaxValue, -Double.MaxValue))
  def of(points: Iterable[Vec3]): Box = points.foldLeft(empty)(_ include _)
}
