package mapm.numerics

/** Seeded inputs for the cond check, as arrays (qx, qy, qz, px, py, pz, h) of bit patterns of
  * format `f`, mixing the cases that matter: photons near the sphere |q - p| = h, distances exactly
  * equal to h (Pythagorean quadruples, so that d2 == hh exactly), zero distance, short mantissas
  * (rounding ties), huge and tiny coordinates (overflow, flush) and arbitrary patterns (NaN,
  * infinity, denormals, negative h). */
final class CondGen(f: FloatFormat, seed: Long) {
  private val g = new FloatGen(f, seed)
  private val rnd = g.rnd

  /** Rounds a double to the format; a value it cannot carry becomes a signed infinity. */
  private def enc(d: Double): Long = f.tryEncode(d).getOrElse(f.pack(if (d < 0) 1 else 0, f.expMax, 0))
  private def value(b: Long): Double = f.decode(b)
  private def pow2(k: Int): Double = java.lang.Math.scalb(1.0, k)
  /** A random binade exponent inside the format's normal range, roughly within `spread` of 1. */
  private def scaleExp(spread: Int): Int = math.max(f.minExp + 2, math.min(f.maxExp - 2, rnd.nextInt(2 * spread + 1) - spread))

  private val quadruples = Array((1, 2, 2, 3), (2, 3, 6, 7), (1, 4, 8, 9), (4, 4, 7, 9), (2, 6, 9, 11),
    (6, 6, 7, 11), (3, 4, 12, 13), (2, 5, 14, 15), (2, 10, 11, 15), (1, 12, 12, 17), (8, 9, 12, 17))

  def next(): Array[Long] = rnd.nextInt(10) match {
    case 0 | 1 | 2 => near()
    case 3 => exactDistance()
    case 4 => zeroDistance()
    case 5 => alongAxis()
    case 6 => shortMantissas()
    case 7 => Array.fill(7)(g.operand())
    case 8 => extremes()
    case _ => if (rnd.nextBoolean()) near() else exactDistance()
  }

  /** q near p, h around the distance. */
  def near(): Array[Long] = {
    val k = scaleExp(12)
    val p = Array.fill(3)(enc((rnd.nextDouble() * 2 - 1) * pow2(k)))
    val s = pow2(k - rnd.nextInt(math.min(20, f.manWidth + 4)))
    val q = p.map(pi => enc(value(pi) + (rnd.nextDouble() * 2 - 1) * s))
    val dist = math.sqrt(q.indices.map(i => math.pow(value(q(i)) - value(p(i)), 2)).sum)
    val h = enc(dist * (1 + (rnd.nextDouble() - 0.5) * pow2(-rnd.nextInt(f.manWidth + 2))))
    q ++ p :+ h
  }

  /** |q - p| = h exactly (d^2 = a^2 + b^2 + c^2 with all values small integers times 2^k), and h
    * sometimes moved by one ulp either way. */
  def exactDistance(): Array[Long] = {
    val (a, b, c, d) = quadruples(rnd.nextInt(quadruples.length))
    val perm = rnd.shuffle(Seq(a, b, c))
    val k = scaleExp(8)
    val grid = pow2(k)
    val p = Array.fill(3)(enc((rnd.nextInt(64) - 32) * grid))
    val q = Array.tabulate(3)(i => enc(value(p(i)) + (if (rnd.nextBoolean()) perm(i) else -perm(i)) * grid))
    val h = enc(d * grid)
    val hMoved = rnd.nextInt(4) match {
      case 0 => h + 1 // next pattern up (positive h)
      case 1 => h - 1
      case _ => h
    }
    q ++ p :+ hMoved
  }

  /** q = p: d2 = 0, which is below hh unless h is 0, tiny (hh flushes), or NaN. */
  def zeroDistance(): Array[Long] = {
    val p = Array.fill(3)(if (rnd.nextInt(4) == 0) g.operand() else enc((rnd.nextDouble() * 2 - 1) * pow2(scaleExp(10))))
    val h = rnd.nextInt(3) match {
      case 0 => g.operand()
      case 1 => f.pack(0, g.expIn(1, f.bias / 2 + 1), g.mantissa()) // tiny: h*h may flush to zero
      case _ => enc(rnd.nextDouble() * pow2(scaleExp(10)))
    }
    p ++ p :+ h
  }

  /** q differs from p in one coordinate, by h or by h's neighbours. */
  def alongAxis(): Array[Long] = {
    val p = Array.fill(3)(enc((rnd.nextDouble() * 2 - 1) * pow2(scaleExp(10))))
    val h = enc(rnd.nextDouble() * pow2(scaleExp(10)))
    val axis = rnd.nextInt(3)
    val q = p.clone()
    q(axis) = enc(value(p(axis)) + (if (rnd.nextBoolean()) 1 else -1) * value(h + rnd.nextInt(3) - 1))
    q ++ p :+ h
  }

  /** Coordinates with few mantissa bits, so that squares and sums often round at exact ties. */
  def shortMantissas(): Array[Long] = {
    val k = f.bias + scaleExp(4)
    val t = 1 + rnd.nextInt(math.max(1, f.manWidth / 2 + 1))
    Array.fill(7)(f.pack(0, g.clampExp(k + rnd.nextInt(5) - 2), g.shortMantissa(t))).zipWithIndex.map {
      case (b, i) => if (i < 6 && rnd.nextBoolean()) b | (1L << (f.width - 1)) else b
    }
  }

  /** Coordinates near the largest or smallest exponents: squares overflow or flush. */
  def extremes(): Array[Long] = {
    val high = rnd.nextBoolean()
    def coord(): Long =
      if (high) f.pack(g.sign(), g.expIn(f.bias + (f.maxExp - 2) / 2, f.expMax - 1), g.mantissa())
      else f.pack(g.sign(), g.expIn(1, f.bias / 2 + 2), g.mantissa())
    Array.fill(6)(coord()) :+ (coord() & (f.mask >>> 1))
  }
}
