package mapm.numerics

/** The shader operation's distance condition (3.6.1): is the photon inside the query point's
  * kernel radius h? Bit-exact model of the hardware `mapm.shader.CondCheck`.
  *
  * Computed in the format, every operation rounded by [[SoftFloat]] (nearest even, flush to zero),
  * in exactly this order:
  * {{{
  *   dx = qx - px;  dy = qy - py;  dz = qz - pz
  *   d2 = (dx*dx + dy*dy) + dz*dz
  *   hh = h*h
  *   cond = d2 < hh        (false when either is a NaN)
  * }}}
  */
object CondModel {

  /** cond on bit patterns of format `f`. */
  def cond(f: FloatFormat, qx: Long, qy: Long, qz: Long, px: Long, py: Long, pz: Long, h: Long): Boolean = {
    val dx = SoftFloat.sub(f, qx, px)
    val dy = SoftFloat.sub(f, qy, py)
    val dz = SoftFloat.sub(f, qz, pz)
    val xy = SoftFloat.add(f, SoftFloat.mul(f, dx, dx), SoftFloat.mul(f, dy, dy))
    val d2 = SoftFloat.add(f, xy, SoftFloat.mul(f, dz, dz))
    SoftFloat.lt(f, d2, SoftFloat.mul(f, h, h))
  }

  /** cond for a query point `q`, a photon position `p` and radius `h` given as doubles, each first
    * rounded to `f` ([[FloatFormat.encode]]: a value that `f` cannot carry is a MapmError). */
  def cond(f: FloatFormat, q: Vec3, p: Vec3, h: Double): Boolean =
    cond(f, f.encode(q.x, "query x"), f.encode(q.y, "query y"), f.encode(q.z, "query z"),
      f.encode(p.x, "photon x"), f.encode(p.y, "photon y"), f.encode(p.z, "photon z"), f.encode(h, "radius h"))
}
