package mapm.fpu

import mapm.numerics.{FloatFormat, FloatGen}

/** Operand sets shared by the unit tests. */
object FpuTesting {
  /** A bit pattern as the unsigned value a port carries (fp64 patterns fill a Long). */
  def port(bits: Long): BigInt = if (bits >= 0) BigInt(bits) else BigInt(bits) + (BigInt(1) << 64)

  /** Seeded hard-case operand pairs (see [[FloatGen]]), as two arrays. */
  def randomPairs(f: FloatFormat, count: Int, seed: Long): (Array[Long], Array[Long]) = {
    val g = new FloatGen(f, seed)
    val a = new Array[Long](count)
    val b = new Array[Long](count)
    for (i <- 0 until count) { val (x, y) = g.pair(); a(i) = x; b(i) = y }
    (a, b)
  }

  /** Every ordered pair of the format's bit patterns: pair i is (i mod 2^w, i / 2^w). */
  def exhaustivePair(f: FloatFormat, i: Int): (Long, Long) = (i.toLong & f.mask, i.toLong >>> f.width)
}
