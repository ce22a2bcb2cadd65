package mapm.numerics

/** Bit-accurate model of the Tree Search Accelerator (dissertation 3.4): for bit patterns p, h, s
  * of a [[FloatFormat]] it gives the TC_L = (p-h < s) and TC_R = (p+h > s) bits the hardware
  * (`mapm.tsearch.TSA`) outputs, by the same algorithm:
  *
  *  1. Alignment (3.4.3, 3.4.4): every significand (hidden bit included; exponent field 0 is the
  *     value 0) is shifted right by (largest exponent - own exponent) inside a window of
  *     `manWidth + 1 + guardBits` bits; with `sticky`, one more bit below the window is the OR of
  *     everything shifted out of it.
  *  2. Comparison (3.4.6): a pipelined comparator decides the sign of A - B - C on the aligned
  *     words, most significant bit first, one bit per slice, handing (done, result) from slice
  *     to slice. TC_L compares p - h with s; TC_R swaps p and s (s - h < p).
  *
  * Exactness. The dissertation's alignment ([[Alignment.dissertation]]: n-bit window, bits
  * shifted out are dropped) can decide wrongly: truncation moves A - B - C by more than -1 and
  * less than +2 units of the window's last place, so a decision can be wrong only when
  * |p - h - s| (or |s - h - p|) is below 2 ulp of the largest exponent, and only when bits were
  * shifted out (for example p = s = 1, h = 2^-30 gives TC_L = TC_R = false, losing both
  * children). One guard bit plus a sticky bit ([[Alignment.exact]], what the hardware uses) make
  * every decision exact: a single sticky operand only breaks a tie the right way, and two sticky
  * operands are each below 2^(E-1) (E the largest exponent) so the third operand, at E,
  * dominates their sum by at least two units of the last place. The tests check this
  * exhaustively on small formats against exact rational arithmetic.
  *
  * Inputs must be non-negative and finite; -0 counts as 0. A negative non-zero value, an
  * infinity or a NaN sets `error`, and then both TC bits are 1 (traverse both children: a
  * flagged operation never drops photons silently).
  */
object TsaModel {

  /** How significands are aligned: `guardBits` zero bits below the significand, then an
    * optional sticky bit. */
  final case class Alignment(guardBits: Int, sticky: Boolean) {
    require(guardBits >= 0, s"guard bits must be non-negative, got $guardBits")
    /** Serial word width: the number of comparator slices. */
    def wordWidth(fmt: FloatFormat): Int = fmt.manWidth + 1 + guardBits + (if (sticky) 1 else 0)
  }

  object Alignment {
    /** What the hardware does: one guard bit and a sticky bit, exact for every input. */
    val exact: Alignment = Alignment(guardBits = 1, sticky = true)
    /** 3.4 as written: the hidden bit and mantissa only, bits shifted out are lost. */
    val dissertation: Alignment = Alignment(guardBits = 0, sticky = false)
  }

  /** The TSA outputs for one operation. */
  final case class Outcome(tcl: Boolean, tcr: Boolean, error: Boolean)

  /** Cycles from an operation entering the TSA to its outcome: four alignment stages (exponent
    * differences; shift amounts; the shifters' upper levels; their lower levels) plus one cycle
    * per comparator slice. */
  def latency(fmt: FloatFormat, al: Alignment = Alignment.exact): Int = al.wordWidth(fmt) + 4

  /** True when `bits` is not a valid TSA input: negative and non-zero, infinite or NaN. */
  def inputError(fmt: FloatFormat, bits: Long): Boolean =
    !fmt.isFinite(bits) || (fmt.sign(bits) == 1 && !fmt.isZero(bits))

  /** The significand with its hidden bit, `manWidth + 1` bits; 0 when the exponent field is 0. */
  def significand(fmt: FloatFormat, bits: Long): Long =
    if (fmt.isZero(bits)) 0L else (1L << fmt.manWidth) | fmt.manField(bits)

  /** Right-shift distance of each operand's significand: largest exponent field minus its own. */
  def shiftAmounts(pe: Int, he: Int, se: Int): (Int, Int, Int) = {
    val m = pe max he max se
    (m - pe, m - he, m - se)
  }

  /** The aligned word of `bits` shifted right by `shift`: significand, `guardBits` zeros, then
    * the sticky bit (OR of the bits shifted below the guard bits) when the alignment has one. */
  def align(fmt: FloatFormat, bits: Long, shift: Int, al: Alignment): Long = {
    require(shift >= 0, s"shift must be non-negative, got $shift")
    val window = significand(fmt, bits) << al.guardBits // manWidth + 1 + guardBits <= 54 bits
    val kept = if (shift >= 63) 0L else window >>> shift
    if (!al.sticky) kept
    else {
      val lost = if (shift >= 63) window != 0 else (window & ((1L << shift) - 1)) != 0
      (kept << 1) | (if (lost) 1L else 0L)
    }
  }

  /** Comparator state between slices: `done` says the sign of A - B - C is decided; `result`
    * is then 1 for positive, 0 for negative. While not done, `result` is the carry R in {0, 1}:
    * the value of the bits seen so far, A - B - C truncated to them. */
  final case class SliceState(done: Boolean, result: Boolean)

  /** The state before the first slice. */
  val initialState: SliceState = SliceState(done = false, result = false)

  /** One comparator slice (Table 3.7): with R the carry, R' = 2R + a - b - c; R' >= 2 decides
    * positive and R' <= -1 negative (the remaining bits move the value by at most +1 / -2 units
    * of this slice's weight), otherwise R' is the next carry. A decided state passes through. */
  def slice(st: SliceState, a: Int, b: Int, c: Int): SliceState =
    if (st.done) st
    else {
      val r = 2 * (if (st.result) 1 else 0) + a - b - c
      if (r >= 2) SliceState(done = true, result = true)
      else if (r <= -1) SliceState(done = true, result = false)
      else SliceState(done = false, result = r == 1)
    }

  /** The comparator's final state for `width`-bit words a, b, c, fed MSB first. */
  def compare(a: Long, b: Long, c: Long, width: Int): SliceState = {
    var st = initialState
    var i = width - 1
    while (i >= 0) {
      st = slice(st, ((a >>> i) & 1L).toInt, ((b >>> i) & 1L).toInt, ((c >>> i) & 1L).toInt)
      i -= 1
    }
    st
  }

  /** A - B < C from the comparator's final state: decided and negative. After the last slice an
    * undecided state holds A - B - C itself: 0 (equal) or 1 (positive by one unit). */
  def less(st: SliceState): Boolean = st.done && !st.result

  /** The TSA's outputs for p, h, s. */
  def evaluate(fmt: FloatFormat, p: Long, h: Long, s: Long, al: Alignment = Alignment.exact): Outcome = {
    if (inputError(fmt, p) || inputError(fmt, h) || inputError(fmt, s)) Outcome(tcl = true, tcr = true, error = true)
    else {
      val (sp, sh, ss) = shiftAmounts(fmt.expField(p), fmt.expField(h), fmt.expField(s))
      val ap = align(fmt, p, sp, al)
      val ah = align(fmt, h, sh, al)
      val as = align(fmt, s, ss, al)
      val w = al.wordWidth(fmt)
      Outcome(tcl = less(compare(ap, ah, as, w)), tcr = less(compare(as, ah, ap, w)), error = false)
    }
  }
}
