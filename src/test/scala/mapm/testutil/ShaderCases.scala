package mapm.testutil

import mapm.numerics.FloatFormat

/** Seeded random shader operations in the style of shader-chain.md §7: kernel, h and power with
  * exponents around 1.0, BRDF and contribution in (0, 1] (3 % exactly 1.0), 15 % of all operands
  * with short significands (only a few leading fraction bits set). The exponent spread is ±20
  * where the format allows it, so that some results of narrow formats overflow or underflow. */
final class ShaderCases(val format: FloatFormat, seed: Long) {
  private val rnd = new scala.util.Random(seed)
  private val spread = math.min(20, format.bias / 2)

  private def fraction(): Long =
    if (rnd.nextDouble() < 0.15) {
      val keep = 1 + rnd.nextInt(math.min(4, format.manWidth))
      (rnd.nextLong() & ((1L << keep) - 1)) << (format.manWidth - keep)
    } else rnd.nextLong() & format.manMask

  private def around(center: Int, lo: Int, hi: Int): Long =
    format.pack(0, center + lo + rnd.nextInt(hi - lo + 1), fraction())

  /** A positive operand with value near 1 (exponent field bias ± spread). */
  def scale(): Long = around(format.bias, -spread, spread)

  /** A positive operand in (0, 1]: exactly 1.0 in 3 % of draws. */
  def unit(): Long =
    if (rnd.nextDouble() < 0.03) format.pack(0, format.bias, 0) else around(format.bias, -spread, -1)

  /** One channel's five inputs: kernel, BRDF, h, power, contribution. */
  def channel(): Array[Long] = Array(scale(), unit(), scale(), scale(), unit())

  /** A whole operation: kernel, BRDF, h, then power r/g/b and contribution r/g/b. */
  def operation(): Array[Long] = Array(scale(), unit(), scale(), scale(), scale(), scale(), unit(), unit(), unit())
}
