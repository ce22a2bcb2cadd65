package mapm.numerics

/** Bit-exact floating-point arithmetic on the bit patterns of any [[FloatFormat]], the reference
  * that the conventional hardware units (`mapm.fpu`) reproduce bit for bit.
  *
  * Everything is integer arithmetic on `Long`s (no `Double` anywhere), so it is exact for every
  * format from e2m1 to e11m52, and it allocates nothing.
  *
  * Conventions (the project's, see docs/fpu.md):
  *  - '''Rounding''': round to nearest, ties to even, of the exact result.
  *  - '''Flush on input''': an operand with exponent field 0 is a zero of its sign, whatever its
  *    mantissa field (denormals are read as zero).
  *  - '''Flush on output''': the exact result is first rounded to `manWidth` fraction bits with an
  *    unbounded exponent; if that rounded value is below the smallest normal it becomes a zero
  *    carrying the sign of the exact result. (So a value just below the smallest normal that
  *    rounds up to it is kept; this is what [[FloatFormat.tryEncode]] does for doubles.)
  *  - '''Overflow''': a rounded value above the largest finite one becomes infinity of its sign
  *    (IEEE round-to-nearest).
  *  - '''Zeros''': signs as in IEEE under round-to-nearest: an exact zero sum of operands of
  *    opposite sign (x - x) is +0, (-0) + (-0) = -0, a product or quotient has the XOR of the signs.
  *  - '''Infinity and NaN''' follow IEEE: inf - inf, 0 * inf, 0 / 0 and inf / inf are invalid;
  *    x / 0 is an infinity. Every NaN result is the canonical quiet NaN [[FloatFormat.quietNaN]]
  *    (payloads are not propagated). [[lt]] is false when either operand is a NaN, and -0 < +0 is
  *    false.
  */
object SoftFloat {

  def add(f: FloatFormat, a: Long, b: Long): Long = addMagnitudes(f, a, b, bSign = f.sign(b))

  /** a - b: a + (-b), with the sign of b flipped before anything else. */
  def sub(f: FloatFormat, a: Long, b: Long): Long = addMagnitudes(f, a, b, bSign = f.sign(b) ^ 1)

  def mul(f: FloatFormat, a: Long, b: Long): Long = {
    val ea = f.expField(a); val eb = f.expField(b)
    val s = f.sign(a) ^ f.sign(b)
    if (ea == f.expMax || eb == f.expMax) {
      if (f.isNaN(a) || f.isNaN(b) || ea == 0 || eb == 0) f.quietNaN // NaN, or 0 * inf
      else f.pack(s, f.expMax, 0)
    } else if (ea == 0 || eb == 0) f.pack(s, 0, 0)
    else {
      val ma = (1L << f.manWidth) | f.manField(a)
      val mb = (1L << f.manWidth) | f.manField(b)
      val lsbExp = ea + eb - 2 * (f.bias + f.manWidth)
      if (f.manWidth <= 30) roundPack(f, s, lsbExp, ma * mb) // product below 2^62
      else {
        // 128-bit product hi:lo (below 2^106), brought down to 62 bits with a sticky bit.
        val hi = Math.multiplyHigh(ma, mb)
        val lo = ma * mb
        val len = if (hi != 0) 128 - java.lang.Long.numberOfLeadingZeros(hi) else 64 - java.lang.Long.numberOfLeadingZeros(lo)
        if (len <= 62) roundPack(f, s, lsbExp, lo)
        else {
          val k = len - 62
          val kept = (hi << (64 - k)) | (lo >>> k)
          val sticky = if ((lo & ((1L << k) - 1)) != 0) 1L else 0L
          roundPack(f, s, lsbExp + k, kept | sticky)
        }
      }
    }
  }

  def div(f: FloatFormat, a: Long, b: Long): Long = {
    val ea = f.expField(a); val eb = f.expField(b)
    val s = f.sign(a) ^ f.sign(b)
    if (f.isNaN(a) || f.isNaN(b)) f.quietNaN
    else if (ea == f.expMax) { if (eb == f.expMax) f.quietNaN else f.pack(s, f.expMax, 0) }
    else if (eb == f.expMax) f.pack(s, 0, 0)
    else if (eb == 0) { if (ea == 0) f.quietNaN else f.pack(s, f.expMax, 0) }
    else if (ea == 0) f.pack(s, 0, 0)
    else {
      val mb = (1L << f.manWidth) | f.manField(b)
      var r = (1L << f.manWidth) | f.manField(a)
      var lsbExp = ea - eb
      if (r < mb) { r <<= 1; lsbExp -= 1 } // now mb <= r < 2 mb: the first quotient bit is 1
      // Restoring division: manWidth + 3 quotient bits (hidden bit, fraction, guard, round).
      val qBits = f.manWidth + 3
      var q = 0L
      var i = 0
      while (i < qBits) {
        q <<= 1
        if (r >= mb) { r -= mb; q |= 1 }
        r <<= 1
        i += 1
      }
      roundPack(f, s, lsbExp - (qBits - 1) - 1, (q << 1) | (if (r != 0) 1L else 0L))
    }
  }

  /** a < b; false when either is a NaN; zeros of either sign (and denormal patterns) are equal. */
  def lt(f: FloatFormat, a: Long, b: Long): Boolean =
    !f.isNaN(a) && !f.isNaN(b) && orderKey(f, a) < orderKey(f, b)

  /** A signed integer that orders the non-NaN patterns of `f` by value. */
  private def orderKey(f: FloatFormat, x: Long): Long = {
    val mag = if (f.expField(x) == 0) 0L else x & (f.mask >>> 1)
    if (f.sign(x) == 1) -mag else mag
  }

  /** a + (b with its sign replaced by `bSign`). */
  private def addMagnitudes(f: FloatFormat, a: Long, b: Long, bSign: Int): Long = {
    val ea = f.expField(a); val eb = f.expField(b)
    val sa = f.sign(a)
    if (ea == f.expMax || eb == f.expMax) {
      if (f.isNaN(a) || f.isNaN(b)) f.quietNaN
      else if (ea == f.expMax && eb == f.expMax) { if (sa == bSign) f.pack(sa, f.expMax, 0) else f.quietNaN }
      else if (ea == f.expMax) f.pack(sa, f.expMax, 0)
      else f.pack(bSign, f.expMax, 0)
    } else if (eb == 0) {
      if (ea == 0) f.pack(sa & bSign, 0, 0) else a // adding a zero is exact
    } else if (ea == 0) f.pack(bSign, eb, f.manField(b))
    else {
      val ma = (1L << f.manWidth) | f.manField(a)
      val mb = (1L << f.manWidth) | f.manField(b)
      val aBigger = ea > eb || (ea == eb && ma >= mb)
      val eBig = if (aBigger) ea else eb
      val mBig = if (aBigger) ma else mb
      val sBig = if (aBigger) sa else bSign
      val mSmall = if (aBigger) mb else ma
      // Three extra low bits: guard, round and a sticky bit that ORs everything shifted out.
      val big = mBig << 3
      val d = math.abs(ea - eb)
      val small =
        if (d == 0) mSmall << 3
        else if (d >= f.manWidth + 4) 1L // the whole small operand is sticky
        else {
          val full = mSmall << 3
          (full >>> d) | (if ((full & ((1L << d) - 1)) != 0) 1L else 0L)
        }
      val sum = if (sa == bSign) big + small else big - small
      if (sum == 0) 0L // exact cancellation: +0 under round to nearest
      else roundPack(f, sBig, eBig - f.bias - f.manWidth - 3, sum)
    }
  }

  /** Rounds sig * 2^lsbExp (sig > 0, below 2^62) to the format and packs it with sign `s`.
    *
    * Bits of `sig` below its top manWidth+3 may be a sticky summary of lower bits (any nonzero
    * tail marked by a 1 there): rounding only looks at the half-ulp bit and whether anything
    * below it is set, so it is correct as long as the sticky bit sits below the half-ulp bit. */
  private def roundPack(f: FloatFormat, s: Int, lsbExp: Int, sig: Long): Long = {
    val n = f.manWidth + 1
    var sh = 64 - java.lang.Long.numberOfLeadingZeros(sig) - n
    var q =
      if (sh <= 0) sig << -sh
      else {
        val kept = sig >>> sh
        val rem = sig & ((1L << sh) - 1)
        val half = 1L << (sh - 1)
        if (rem > half || (rem == half && (kept & 1L) == 1L)) kept + 1 else kept
      }
    if ((q >>> n) != 0) { q >>>= 1; sh += 1 }
    val e = lsbExp + sh + f.manWidth // unbiased exponent of the leading bit
    if (e > f.maxExp) f.pack(s, f.expMax, 0)
    else if (e < f.minExp) f.pack(s, 0, 0)
    else f.pack(s, e + f.bias, q & f.manMask)
  }
}
