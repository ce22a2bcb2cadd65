package mapm.model

import mapm.numerics._

/** Image comparison figures. */
object Metrics {
  /** Peak signal-to-noise ratio of `test` against `reference` (same length, any linear values), in
    * dB, with the peak taken as the reference's largest value: 10 log10(peak^2 / MSE). Infinite
    * when the two are equal; 0 for an all-zero reference that differs. */
  def psnr(test: Array[Double], reference: Array[Double]): Double = {
    require(test.length == reference.length, s"psnr: ${test.length} values against ${reference.length}")
    var se = 0.0
    var peak = 0.0
    var i = 0
    while (i < test.length) {
      val d = test(i) - reference(i)
      se += d * d
      peak = math.max(peak, math.abs(reference(i)))
      i += 1
    }
    if (se == 0) Double.PositiveInfinity
    else if (peak == 0) 0.0
    else 10 * math.log10(peak * peak / (se / test.length))
  }
}
