package mapm.numerics

import mapm.numerics.ShaderChainModel.{Flags, Result}

/** The conventional shader chain, bit for bit: the colour of one channel as four IEEE-754
  * operations of the format, each rounded to nearest even ([[SoftFloat]]),
  * {{{
  *   t1 = RN(kernel * brdf);  t2 = RN(t1 / h);  t3 = RN(t2 * power);  colour = RN(t3 * contrib)
  * }}}
  * with the special cases and output rules of the online chain (shader-chain.md section 2,
  * ../shared/vectors/conventional/README.md): any Inf or NaN input, or a zero or subnormal h,
  * gives the quiet NaN with INV; else a zero or subnormal kernel, BRDF, power or contribution
  * gives +0 (UNF when one of them was subnormal); else the first intermediate whose rounded
  * exponent overflows makes the colour the largest finite value of the sign (OVF), and the first
  * that underflows makes it +0 (UNF).
  *
  * Under the last rule every input is a normal number, so [[SoftFloat]]'s own rules tell the
  * story: an intermediate that overflows is an infinity (and every later one stays infinite), one
  * that underflows is a zero (and every later one stays zero). The rule therefore reads the last
  * product alone; the sign of any of them is the XOR of the five input signs. The hardware
  * `mapm.shader.ConvShaderChain` decides the same way.
  */
object ConvChainModel {

  /** Rules 1 and 2 for one channel: their result, or null when the channel is computed. */
  def special(f: FloatFormat, kernel: Long, brdf: Long, h: Long, power: Long, contrib: Long): Result = {
    def zero(x: Long) = f.expField(x) == 0
    def flushed(x: Long) = zero(x) && f.manField(x) != 0
    if (!f.isFinite(kernel) || !f.isFinite(brdf) || !f.isFinite(h) || !f.isFinite(power) || !f.isFinite(contrib) ||
        zero(h)) Invalid(f)
    else if (zero(kernel) || zero(brdf) || zero(power) || zero(contrib))
      if (flushed(kernel) || flushed(brdf) || flushed(power) || flushed(contrib)) Flushed else Zero
    else null
  }

  // The special results, made once (the model runs per channel of every SO of a frame).
  private val Zero = Result(0L, 0)
  private val Flushed = Result(0L, Flags.UNF)
  private def Invalid(f: FloatFormat) = Result(f.quietNaN, Flags.INV)

  /** The shared part of the three channels: t2 = RN(RN(kernel * brdf) / h). */
  def front(f: FloatFormat, kernel: Long, brdf: Long, h: Long): Long =
    SoftFloat.div(f, SoftFloat.mul(f, kernel, brdf), h)

  /** The output rule on the last product t4 (inputs all normal): overflow, underflow or t4. */
  def output(f: FloatFormat, t4: Long): Result = {
    val e = f.expField(t4)
    if (e == f.expMax) Result(f.pack(f.sign(t4), f.expMax - 1, f.manMask), Flags.OVF)
    else if (e == 0) Result(0L, Flags.UNF)
    else Result(t4, 0)
  }

  /** One channel from the shared part t2 (see [[front]]). */
  def channel(f: FloatFormat, kernel: Long, brdf: Long, h: Long, t2: Long, power: Long, contrib: Long): Result = {
    val sp = special(f, kernel, brdf, h, power, contrib)
    if (sp != null) sp else output(f, SoftFloat.mul(f, SoftFloat.mul(f, t2, power), contrib))
  }

  /** [[colour]] as the vector files compare it (no internals: the conventional files have none). */
  def trace(f: FloatFormat, kernel: Long, brdf: Long, h: Long, power: Long, contrib: Long): ShaderChainModel.Trace = {
    val r = colour(f, kernel, brdf, h, power, contrib)
    ShaderChainModel.Trace(r.bits, r.flags, None)
  }

  /** One channel of one operation. */
  def colour(f: FloatFormat, kernel: Long, brdf: Long, h: Long, power: Long, contrib: Long): Result =
    channel(f, kernel, brdf, h, front(f, kernel, brdf, h), power, contrib)
}
