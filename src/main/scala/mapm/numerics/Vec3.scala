package mapm.numerics

/** A 3-vector of doubles: positions, directions and RGB triples alike. */
final case class Vec3(x: Double, y: Double, z: Double) {
  def +(o: Vec3): Vec3 = Vec3(x + o.x, y + o.y, z + o.z)
  def -(o: Vec3): Vec3 = Vec3(x - o.x, y - o.y, z - o.z)
  def *(s: Double): Vec3 = Vec3(x * s, y * s, z * s)
  def /(s: Double): Vec3 = Vec3(x / s, y / s, z / s)
  /** Component-wise product (colour times colour). */
  def mul(o: Vec3): Vec3 = Vec3(x * o.x, y * o.y, z * o.z)
  def dot(o: Vec3): Double = x * o.x + y * o.y + z * o.z
  def cross(o: Vec3): Vec3 = Vec3(y * o.z - z * o.y, z * o.x - x * o.z, x * o.y - y * o.x)
  def length: Double = math.sqrt(dot(this))
  def normalized: Vec3 = { val l = length; if (l == 0) this else this / l }
  def unary_- : Vec3 = Vec3(-x, -y, -z)
  /** Component by axis index 0, 1, 2. */
  def apply(axis: Int): Double = axis match { case 0 => x; case 1 => y; case _ => z }
  def min(o: Vec3): Vec3 = Vec3(math.min(x, o.x), math.min(y, o.y), math.min(z, o.z))
  def max(o: Vec3): Vec3 = Vec3(math.max(x, o.x), math.max(y, o.y), math.max(z, o.z))
  def maxComponent: Double = math.max(x, math.max(y, z))
  def isFinite: Boolean = !(x.isNaN || x.isInfinite || y.isNaN || y.isInfinite || z.isNaN || z.isInfinite)
  override def toString: String = s"($x, $y, $z)"
}

object Vec3 {
  val zero: Vec3 = Vec3(0, 0, 0)
  val one: Vec3 = Vec3(1, 1, 1)
}
