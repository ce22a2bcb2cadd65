package mapm.numerics

import mapm.MapmError

/** Bit-accurate model of the online shader chain (../shared/design/shader-chain.md):
  * colour = ((kernel · BRDF) / h) · power · contribution for one channel, on bit patterns of
  * `format`, with g guard digits (every online unit produces N = n + g digits).
  *
  * The significand path is MUL1 (x = kernel bits, y = BRDF), the divider over h with the
  * pre-shifted dividend (0, p1), one quasi-normalization step, MUL2 (x = Q', y = power) and
  * MUL3 (x = p2, y = contribution), all from [[OnlineArith]]; then normalization by m ∈ 0 … 4,
  * truncation to n bits, the exponent E_r = ΣE + 5 − 2^ew − s − m and the special cases of §2.
  *
  * The three channels of one shader operation share MUL1, the divider and QN: [[front]] computes
  * that part once and [[channel]] finishes one channel from it. The instance holds no mutable
  * state, so one instance may serve many threads.
  */
final class ShaderChainModel(val format: FloatFormat, val g: Int) {
  import ShaderChainModel._

  MapmError.check(g >= 0 && g <= 8, s"shader chain: guard digits g = $g outside 0..8")
  MapmError.check(format.manWidth >= 4, s"shader chain: format $format needs at least 4 fraction bits (n ≥ 5)")

  /** Significand width including the hidden bit. */
  val n: Int = format.manWidth + 1
  /** Digits produced by every online unit. */
  val digits: Int = n + g
  MapmError.check(digits + 1 <= DigitString.MaxLength, s"shader chain: N = n + g = $digits is too long for the model")

  private val ew = format.expWidth
  private val expAllOnes = format.expMax
  /** 5 − 2^ew: the constant of the exponent sum. */
  private val expConst = 5 - (1 << ew)

  /** The significand operand 0.1f as n bits. */
  @inline private def sig(bits: Long): Long = (1L << format.manWidth) | format.manField(bits)

  /** MUL1, the divider and QN for one operation; shared by its channels. `special` is the part
    * of the special-case decision that depends on kernel, BRDF and h alone. */
  def front(kernel: Long, brdf: Long, h: Long): Front = {
    val ek = format.expField(kernel); val eb = format.expField(brdf); val eh = format.expField(h)
    val inv = ek == expAllOnes || eb == expAllOnes || eh == expAllOnes || eh == 0
    val zero = ek == 0 || eb == 0
    val sub = (ek == 0 && format.manField(kernel) != 0) || (eb == 0 && format.manField(brdf) != 0)
    val signs = format.sign(kernel) ^ format.sign(brdf) ^ format.sign(h)
    val special = if (inv) SpecialInv else if (zero) { if (sub) SpecialSub else SpecialZero } else 0
    if (inv || zero) return new Front(special, signs, 0, null, null, null, 0)
    val p1 = OnlineArith.mul(DigitString.ofBits(sig(kernel), n), sig(brdf), n, digits)
    val dividend = DigitString(p1.pos, p1.neg, digits + 1) // x' = (0, p1_1, …, p1_N)
    val q = OnlineArith.div(dividend, sig(h), n, digits)
    val s = OnlineArith.qnStep(q)
    new Front(special, signs, ek + eb - eh + expConst - s, p1, q, OnlineArith.qnApply(q, s), s)
  }

  /** One channel: the colour bits and flags (OVF = 1, UNF = 2, INV = 4). */
  def channel(f: Front, power: Long, contrib: Long): Result = {
    val special = specialFlags(f, power, contrib)
    if (special >= 0) specialResult(special) else channel(f, power, mul2(f, power), contrib)
  }

  /** MUL2 of one channel, Q' × power: the part of [[channel]] that depends on the photon alone
    * (null when the operation's front is a special case, which never reads it). */
  def mul2(f: Front, power: Long): DigitString =
    if (f.special != 0) null else OnlineArith.mul(f.qn, sig(power), n, digits)

  /** [[channel]] with MUL2's product `p2 = mul2(f, power)` already known. */
  def channel(f: Front, power: Long, p2: DigitString, contrib: Long): Result = {
    val special = specialFlags(f, power, contrib)
    if (special >= 0) specialResult(special)
    else {
      val p3 = OnlineArith.mul(p2, sig(contrib), n, digits)
      pack(f, power, contrib, p3, shiftOf(p3))
    }
  }

  /** One channel with every intermediate value the test vectors carry. */
  def trace(kernel: Long, brdf: Long, h: Long, power: Long, contrib: Long): Trace = {
    val f = front(kernel, brdf, h)
    val special = specialFlags(f, power, contrib)
    if (special >= 0) {
      val r = specialResult(special)
      Trace(r.bits, r.flags, None)
    } else {
      val p2 = OnlineArith.mul(f.qn, sig(power), n, digits)
      val p3 = OnlineArith.mul(p2, sig(contrib), n, digits)
      val m = shiftOf(p3)
      val r = pack(f, power, contrib, p3, m)
      Trace(r.bits, r.flags, Some(Internals(f.s, m, exponent(f, power, contrib, m), f.p1, f.q, p2, p3)))
    }
  }

  /** The colour of one channel of one operation (computes the shared part too). */
  def colour(kernel: Long, brdf: Long, h: Long, power: Long, contrib: Long): Result =
    channel(front(kernel, brdf, h), power, contrib)

  /** Rules 1 and 2 of §2 for the whole channel: their flags, or -1 when neither applies. */
  private def specialFlags(f: Front, power: Long, contrib: Long): Int = {
    val ep = format.expField(power); val ec = format.expField(contrib)
    if (f.special == SpecialInv || ep == expAllOnes || ec == expAllOnes) Flags.INV
    else if (f.special != 0 || ep == 0 || ec == 0) {
      val sub = f.special == SpecialSub || (ep == 0 && format.manField(power) != 0) ||
        (ec == 0 && format.manField(contrib) != 0)
      if (sub) Flags.UNF else 0
    } else -1
  }

  private def specialResult(flags: Int): Result =
    if (flags == Flags.INV) Result(format.quietNaN, Flags.INV) else Result(0L, flags)

  /** The final normalization shift m: P3·2^m ∈ [1/2, 1). */
  private def shiftOf(p3: DigitString): Int = {
    val v = p3.scaled
    val m = digits - (64 - java.lang.Long.numberOfLeadingZeros(v))
    if (v <= 0 || m > MaxShift)
      throw new IllegalStateException(s"shader chain: P3 = $p3 outside [2^-5, 1), which the chain's ranges exclude")
    m
  }

  /** E_r = ΣE + 5 − 2^ew − s − m (before saturation or flush). */
  private def exponent(f: Front, power: Long, contrib: Long, m: Int): Int =
    f.expSum + format.expField(power) + format.expField(contrib) - m

  /** Rule 3: truncation of P3·2^m to n bits, then saturation (3a), flush (3b) or packing (3c). */
  private def pack(f: Front, power: Long, contrib: Long, p3: DigitString, m: Int): Result = {
    val e = exponent(f, power, contrib, m)
    if (e >= expAllOnes) Result(format.pack(f.signs ^ format.sign(power) ^ format.sign(contrib), expAllOnes - 1, format.manMask), Flags.OVF)
    else if (e <= 0) Result(0L, Flags.UNF)
    else {
      val shift = n + m - digits
      val v = p3.scaled
      val significand = if (shift >= 0) v << shift else v >>> -shift
      Result(format.pack(f.signs ^ format.sign(power) ^ format.sign(contrib), e, significand & format.manMask), 0)
    }
  }

  /** The exact colour of finite inputs in Double arithmetic, for error measurement (decodes
    * as the chain reads its inputs: exponent field 0 is zero). */
  def reference(kernel: Long, brdf: Long, h: Long, power: Long, contrib: Long): Double =
    format.decode(kernel) * format.decode(brdf) / format.decode(h) * format.decode(power) * format.decode(contrib)

  /** |result − exact| in units in the last place of `exact` (a normal, finite value). */
  def ulpError(bits: Long, exact: Double): Double = {
    val a = math.abs(exact)
    val ulp = java.lang.Math.scalb(1.0, java.lang.Math.getExponent(a) - format.manWidth)
    math.abs(format.decode(bits) - exact) / ulp
  }
}

object ShaderChainModel {
  /** Flag values of the vectors' `flags` column. */
  object Flags {
    val OVF = 1
    val UNF = 2
    val INV = 4
  }

  /** The largest final normalization shift the datapath supports (0.1f alignment). */
  val MaxShift = 4

  private val SpecialInv = 1
  private val SpecialZero = 2
  private val SpecialSub = 3

  /** The shared part of one operation. Fields other than `special` and `signs` are meaningful
    * only when `special` is 0. `expSum` is E_k + E_B − E_h + 5 − 2^ew − s. */
  final class Front private[ShaderChainModel] (
      private[ShaderChainModel] val special: Int,
      private[ShaderChainModel] val signs: Int,
      private[ShaderChainModel] val expSum: Int,
      val p1: DigitString,
      val q: DigitString,
      val qn: DigitString,
      val s: Int)

  /** A colour channel's bit pattern and flags. */
  final case class Result(bits: Long, flags: Int)

  /** The values the vector files carry for a computed (rule 3) row: QN step s, final shift m,
    * biased exponent E before saturation or flush, and the digit strings of MUL1, the divider
    * (before QN), MUL2 and MUL3. */
  final case class Internals(s: Int, m: Int, e: Int, p1: DigitString, q: DigitString, p2: DigitString, p3: DigitString)

  /** Result of [[ShaderChainModel.trace]]; `internals` is None for rules 1 and 2 of §2. */
  final case class Trace(bits: Long, flags: Int, internals: Option[Internals])
}
