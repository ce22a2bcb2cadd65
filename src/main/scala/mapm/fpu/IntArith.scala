package mapm.fpu

import chisel3._
import chisel3.util._

/** Dadda reduction of an unsigned product's partial products to two rows, one level at a time, so
  * that a pipeline register may end any level. A column is the list of bits of one weight. */
private[fpu] object Dadda {
  type Columns = Seq[Seq[Bool]]

  /** The partial products of a * b: column k holds a(j) & b(k - j). */
  def partialProducts(a: UInt, b: UInt): Columns = {
    val (wa, wb) = (a.getWidth, b.getWidth)
    Seq.tabulate(wa + wb)(k => for (j <- 0 until wa if k - j >= 0 && k - j < wb) yield a(j) && b(k - j))
  }

  /** The partial products of a * a, folded: a(i) & a(j) and a(j) & a(i) (i < j) are one bit a
    * column higher, and a(i) & a(i) is a(i). Column k holds a(k/2) (k even) and a(i) & a(j) for
    * i < j, i + j = k - 1: about half the bits of [[partialProducts]], the tallest column
    * [[squareHeight]]. */
  def squareProducts(a: UInt): Columns =
    Seq.tabulate(2 * a.getWidth)(k => squareTerms(a.getWidth, k).map { case (i, j) => if (i == j) a(i) else a(i) && a(j) })

  /** The tallest column of [[squareProducts]] for a `w`-bit operand. */
  def squareHeight(w: Int): Int = (0 until 2 * w).map(squareTerms(w, _).size).max

  /** The terms of column k of a `w`-bit square: (k/2, k/2) for k even, and (i, j), i < j, i + j = k - 1. */
  private def squareTerms(w: Int, k: Int): Seq[(Int, Int)] =
    (if (k % 2 == 0 && k / 2 < w) Seq((k / 2, k / 2)) else Nil) ++ (for (i <- 0 until w; j = k - 1 - i if i < j && j < w) yield (i, j))

  /** The column heights each level reduces to, for operands of `n` and `n` bits: Dadda's sequence
    * 2, 3, 4, 6, 9, 13, 19, 28, ... below n, largest first (empty when n <= 2); more generally
    * those below the tallest column `n`. */
  def targets(n: Int): Seq[Int] =
    Iterator.iterate(2)(d => d * 3 / 2).takeWhile(_ < n).toSeq.reverse

  /** One level: full and half adders bring every column to at most `target` bits. */
  def level(cols: Columns, target: Int): Columns = {
    val out = Array.fill(cols.length + 1)(Seq.empty[Bool])
    for (i <- cols.indices) {
      var raw = cols(i)
      var kept = Seq.empty[Bool]
      def height = raw.length + kept.length + out(i).length
      while (height > target) {
        if (height - target == 1 || raw.length == 2) {
          val (x, y) = (raw(0), raw(1))
          kept :+= (x ^ y); out(i + 1) :+= (x && y); raw = raw.drop(2)
        } else {
          val (x, y, z) = (raw(0), raw(1), raw(2))
          kept :+= (x ^ y ^ z); out(i + 1) :+= ((x && y) || (x && z) || (y && z)); raw = raw.drop(3)
        }
      }
      out(i) = out(i) ++ raw ++ kept
    }
    val all = out.toSeq
    if (all.last.isEmpty) all.init else all
  }

  /** The two rows of columns of height at most 2, each `width` bits. */
  def rows(cols: Columns, width: Int): (UInt, UInt) = {
    require(cols.forall(_.length <= 2), "Dadda.rows: a column holds more than two bits")
    def row(k: Int) = VecInit(Seq.tabulate(width)(i => cols.lift(i).flatMap(_.lift(k)).getOrElse(false.B))).asUInt
    (row(0), row(1))
  }
}

/** The state of a Kogge-Stone prefix addition between levels, per bit position (position 0 is the
  * carry-in, position i + 1 bit i): the group generate so far, the group propagate where a later
  * level still reads it (None elsewhere, so that no register holds a dead bit), and the operands'
  * half sums. */
private[fpu] final case class PrefixState(g: Seq[Bool], p: Seq[Option[Bool]], half: Seq[Bool]) {
  /** The state across a pipeline step boundary: each live bit through `cross`. */
  def map(cross: Bool => Bool): PrefixState = PrefixState(g.map(cross), p.map(_.map(cross)), half.map(cross))
}

/** A `width`-bit addition a + b + cin as Kogge-Stone levels, so that a pipeline register may end
  * any level: [[start]] (half sums and the first level), [[level]] for each further span, and
  * [[sum]]. With `carryOut` false the carry out of the top bit is not computed (the caller knows
  * it is zero or does not need it) and the sum has `width` bits, else `width` + 1. */
private[fpu] object PrefixAdd {
  private def positions(width: Int, carryOut: Boolean) = width + (if (carryOut) 1 else 0)

  /** Spans of the levels: 1, 2, 4, ... below the number of positions. */
  def spans(width: Int, carryOut: Boolean = true): Seq[Int] =
    Iterator.iterate(1)(_ * 2).takeWhile(_ < positions(width, carryOut)).toSeq

  /** Generate and propagate of each position (the carry-in at position 0), then the first level. */
  def start(a: UInt, b: UInt, cin: Bool, width: Int, carryOut: Boolean = true): PrefixState = {
    val n = positions(width, carryOut)
    val half = (0 until width).map(i => a(i) ^ b(i))
    val g = cin +: (0 until n - 1).map(i => a(i) && b(i))
    val p = false.B +: half.take(n - 1)
    level(PrefixState(g, p.map(Some(_)), half), 1)
  }

  /** One level: each position combines with the position `span` below it. A position below
    * 2 * span is then complete, and its propagate is dropped. */
  def level(s: PrefixState, span: Int): PrefixState = {
    val n = s.g.length
    val g = (0 until n).map(j => if (j < span) s.g(j) else s.g(j) || (s.p(j).get && s.g(j - span)))
    val p = (0 until n).map(j => if (j < 2 * span) None else Some(s.p(j).get && s.p(j - span).get))
    PrefixState(g, p, s.half)
  }

  /** a + b + cin: bit i is half(i) ^ carry into i, with the carry out on top when computed. */
  def sum(s: PrefixState): UInt = {
    val bits = s.half.indices.map(i => s.half(i) ^ s.g(i))
    VecInit(if (s.g.length > s.half.length) bits :+ s.g(s.half.length) else bits).asUInt
  }
}
