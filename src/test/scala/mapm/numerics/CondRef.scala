package mapm.numerics

/** Reference for the cond check built only from [[ExactFloat]]: the same operation sequence as
  * the design (dx = qx - px, ...; d2 = (dx*dx + dy*dy) + dz*dz; hh = h*h; d2 < hh), every step the
  * exact rational result correctly rounded, counting the steps that rounded an exact tie. */
object CondRef {
  final case class Trace(d2: Long, hh: Long, cond: Boolean, ties: Int)

  /** `in` = (qx, qy, qz, px, py, pz, h) as bit patterns of `f`. */
  def apply(f: FloatFormat, in: Array[Long]): Trace = {
    import ExactFloat._
    var ties = 0
    def rounded(v: Value): Long = { if (isTie(f, v)) ties += 1; encode(f, v) }
    def dec(b: Long): Value = decode(f, b)
    val d = Array.tabulate(3)(i => rounded(sum(dec(in(i)), negate(dec(in(i + 3))))))
    val sq = d.map(x => rounded(product(dec(x), dec(x))))
    val xy = rounded(sum(dec(sq(0)), dec(sq(1))))
    val d2 = rounded(sum(dec(xy), dec(sq(2))))
    val hh = rounded(product(dec(in(6)), dec(in(6))))
    Trace(d2, hh, less(dec(d2), dec(hh)), ties)
  }
}
