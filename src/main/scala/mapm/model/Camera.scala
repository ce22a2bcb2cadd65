package mapm.model

import mapm.numerics._

import mapm.MapmError

/** A pinhole camera (3.1.5 step 1).
  *
  * The image plane lies one unit in front of `position` along `direction`; its height spans the
  * vertical field of view `fovDeg` and its width follows the image's aspect ratio (square pixels).
  * Image x grows to the camera's right, `direction x up` (a right-handed frame), and image y grows
  * downwards: pixel (0,0) is the top-left corner.
  *
  * @param position  eye point
  * @param direction unit viewing direction
  * @param up        unit vector, the part of it perpendicular to `direction` is the image's up
  * @param fovDeg    vertical field of view in degrees, in (0, 180)
  */
final case class Camera(position: Vec3, direction: Vec3, up: Vec3, fovDeg: Double) {
  MapmError.check(math.abs(direction.length - 1) < 1e-9, s"camera direction $direction is not a unit vector")
  MapmError.check(fovDeg > 0 && fovDeg < 180, s"camera fov must be in (0, 180) degrees, got $fovDeg")
  MapmError.check(direction.cross(up).length > 1e-9, s"camera up $up is parallel to the direction $direction")

  /** Unit vector to the image's right. */
  val right: Vec3 = direction.cross(up).normalized
  /** Unit vector to the image's top, perpendicular to direction and right. */
  val trueUp: Vec3 = right.cross(direction)
  private val tanHalf = math.tan(math.toRadians(fovDeg) / 2)

  /** Unit direction through the point (px, py) of a width x height image, in pixel units
    * (px in [0, width] from the left edge, py in [0, height] from the top edge). */
  def rayDirection(px: Double, py: Double, width: Int, height: Int): Vec3 = {
    val sx = (2 * px / width - 1) * tanHalf * width / height
    val sy = (1 - 2 * py / height) * tanHalf
    (direction + right * sx + trueUp * sy).normalized
  }

  /** Direction of the primary ray through the centre of pixel (x, y). */
  def pixelDirection(x: Int, y: Int, width: Int, height: Int): Vec3 = rayDirection(x + 0.5, y + 0.5, width, height)

  def translate(d: Vec3): Camera = copy(position = position + d)
}

/** Where each pixel's primary ray lands.
  *
  * @param triangle hit triangle per pixel (row-major y * width + x), -1 where the ray misses
  * @param position hit point per pixel (null on a miss), clamped into the scene box
  * @param normal   unit geometric normal at the hit, turned to face the camera (null on a miss)
  * @param view     unit primary-ray direction per pixel
  */
final class PrimaryHits(val width: Int, val height: Int, val triangle: Array[Int], val position: Array[Vec3],
                        val normal: Array[Vec3], val view: Array[Vec3]) {
  def pixels: Int = width * height
  def hit(p: Int): Boolean = triangle(p) >= 0
}

object PrimaryHits {
  /** Traces one ray through every pixel centre. */
  def trace(tree: TriKdTree, camera: Camera, width: Int, height: Int, threads: Int = Parallel.defaultThreads): PrimaryHits = {
    val n = width * height
    val tri = Array.fill(n)(-1)
    val pos = new Array[Vec3](n)
    val nor = new Array[Vec3](n)
    val view = new Array[Vec3](n)
    val queries = new ThreadLocal[TriKdTree.Query] { override def initialValue() = tree.query() }
    Parallel.forRange(n, threads) { p =>
      val q = queries.get
      val d = camera.pixelDirection(p % width, p / width, width, height)
      view(p) = d
      if (q.nearest(camera.position, d)) {
        tri(p) = q.triangle
        pos(p) = tree.scene.clampToBounds(camera.position + d * q.t)
        val g = tree.normals(q.triangle)
        nor(p) = if (g.dot(d) > 0) -g else g
      }
    }
    new PrimaryHits(width, height, tri, pos, nor, view)
  }
}
