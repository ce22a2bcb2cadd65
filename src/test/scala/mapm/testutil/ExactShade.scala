package mapm.testutil

import mapm.numerics.FloatFormat

/** Exact rational reference for the shader chain: kernel·BRDF/h·power·contribution of five
  * normal inputs as num/den·2^E with BigInt num and den, and the error of a result in units in
  * the last place of that exact value. Independent of the model (no online arithmetic). */
object ExactShade {
  private def sig(f: FloatFormat, bits: Long): BigInt = BigInt((1L << f.manWidth) | f.manField(bits))
  private def exp(f: FloatFormat, bits: Long): Int = f.expField(bits) - f.bias - f.manWidth

  /** |result − exact| / ulp(exact) for normal inputs and a normal result of the same sign. */
  def ulpError(f: FloatFormat, k: Long, b: Long, h: Long, p: Long, c: Long, result: Long): Double = {
    val num = sig(f, k) * sig(f, b) * sig(f, p) * sig(f, c)
    val den = sig(f, h)
    val e = exp(f, k) + exp(f, b) - exp(f, h) + exp(f, p) + exp(f, c)
    // l = floor(log2(num / den))
    val a = num.bitLength - den.bitLength
    val l = if ((if (a >= 0) num >= (den << a) else (num << -a) >= den)) a else a - 1
    val mr = sig(f, result)
    val er = exp(f, result)
    // error / ulp = |mr·2^er − num/den·2^e| / 2^(e+l−mw)
    //             = |mr·den·2^(er−e−l+mw) − num·2^(mw−l)| / den
    val sr = er - e - l + f.manWidth
    val sx = f.manWidth - l
    val z = math.min(sr, sx)
    val diff = (mr * den << (sr - z)) - (num << (sx - z))
    java.lang.Math.scalb(diff.abs.toDouble / den.toDouble, z)
  }
}
