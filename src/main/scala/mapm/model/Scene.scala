package mapm.model

import mapm.numerics._

/** A diffuse (Lambertian) material.
  *
  * @param name the name the OBJ/MTL files give it
  * @param kd   diffuse reflectance per RGB channel, each in [0,1]
  * @param ke   emitted radiance per RGB channel (>= 0, watts per unit area per steradian); non-zero
  *             makes every triangle with this material an area light, emitting from its front side
  */
final case class Material(name: String, kd: Vec3, ke: Vec3) {
  def emissive: Boolean = ke.maxComponent > 0
}

/** A triangle with the index of its material in [[Scene.materials]].
  *
  * The front side is the one the counter-clockwise winding v0, v1, v2 faces, i.e. the side the
  * right-handed normal (v1-v0) x (v2-v0) points to. Only emission depends on it; reflection is
  * two-sided.
  */
final case class Triangle(v0: Vec3, v1: Vec3, v2: Vec3, material: Int) {
  /** (v1-v0) x (v2-v0): its length is twice the area. */
  def crossNormal: Vec3 = (v1 - v0).cross(v2 - v0)
  def area: Double = crossNormal.length / 2
  /** Unit front-side normal (zero for a degenerate triangle). */
  def normal: Vec3 = crossNormal.normalized
  def bounds: Box = Box(v0.min(v1).min(v2), v0.max(v1).max(v2))
  def translate(d: Vec3): Triangle = Triangle(v0 + d, v1 + d, v2 + d, material)

  /** Zero area or so close to it that no ray test on it is meaningful: the sine of the angle between
    * its two edges at v0 is below 1e-12 (this includes repeated and collinear vertices). Such
    * triangles are kept in the scene but never hit and never emit. */
  def degenerate: Boolean = {
    val e1 = v1 - v0
    val e2 = v2 - v0
    val c = e1.cross(e2)
    val cc = c.dot(c)
    !(cc > 1e-24 * e1.dot(e1) * e2.dot(e2))
  }
}

/** The geometry of a scene: triangles and their materials, in scene units. */
final case class Scene(triangles: IndexedSeq[Triangle], materials: IndexedSeq[Material]) {
  require(triangles.forall(t => t.material >= 0 && t.material < materials.size), "triangle material index out of range")

  /** Bounding box of all triangle vertices. */
  lazy val bounds: Box = triangles.foldLeft(Box.empty)((b, t) => b.include(t.v0).include(t.v1).include(t.v2))

  /** Length of the bounding box diagonal (at least 1), the scale for ray offsets. */
  lazy val scale: Double = math.max(1.0, bounds.extent.length)

  /** Distance a secondary ray's origin is moved off the surface it leaves (along the normal), so that
    * it does not hit that surface again through rounding: 1e-7 of the scene diagonal. */
  lazy val rayOffset: Double = 1e-7 * scale

  def material(tri: Int): Material = materials(triangles(tri).material)

  /** Indices of the non-degenerate triangles whose material emits: the area lights. */
  lazy val emitters: IndexedSeq[Int] =
    triangles.indices.filter(i => materials(triangles(i).material).emissive && !triangles(i).degenerate)

  def translate(d: Vec3): Scene = Scene(triangles.map(_.translate(d)), materials)

  /** Clamps a point computed on the geometry (a ray hit) into [[bounds]], removing the rounding
    * that could put it a hair outside the box (and so below zero in the positive octant). */
  def clampToBounds(p: Vec3): Vec3 = p.max(bounds.lo).min(bounds.hi)
}

/** A point light: emits `power` (watts per RGB channel) uniformly in all directions from `position`. */
final case class PointLight(position: Vec3, power: Vec3) {
  def translate(d: Vec3): PointLight = copy(position = position + d)
}
