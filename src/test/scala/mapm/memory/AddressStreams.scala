package mapm.memory

import scala.util.Random

/** Read-address streams for the cache tests, all word aligned and inside `[0, span)`. */
object AddressStreams {
  /** Uniformly random words: little locality once `span` exceeds the cache. */
  def uniform(n: Int, span: Int, word: Int, rnd: Random): IndexedSeq[Long] =
    IndexedSeq.fill(n)(rnd.nextInt(span / word).toLong * word)

  /** Root-to-leaf walks down a heap-ordered binary tree of `word`-byte nodes filling `span`, each
    * walk taking a random child at every level: the nodes near the root are read again and again
    * (the pattern of the tree search), the leaves rarely. */
  def treeWalks(n: Int, span: Int, word: Int, rnd: Random): IndexedSeq[Long] = {
    val nodes = span / word
    val out = IndexedSeq.newBuilder[Long]
    var count = 0
    while (count < n) {
      var i = 0
      while (i < nodes && count < n) {
        out += i.toLong * word
        count += 1
        i = 2 * i + 1 + rnd.nextInt(2)
      }
    }
    out.result()
  }

  /** A random walk with short strides, mixed with reads of a small hot region. */
  def local(n: Int, span: Int, word: Int, rnd: Random): IndexedSeq[Long] = {
    val words = span / word
    var at = rnd.nextInt(words)
    IndexedSeq.fill(n) {
      if (rnd.nextInt(4) == 0) rnd.nextInt(words min 64).toLong * word
      else {
        at = Math.floorMod(at + rnd.nextInt(9) - 4, words)
        at.toLong * word
      }
    }
  }

  /** Records of `word` bytes consumed in launch order (the query array seen by the SOQ cache): at
    * each step one of the `window` most recently launched records is read, and the next record
    * is launched with probability 1/`reuse`. */
  def launchOrder(n: Int, span: Int, word: Int, window: Int, reuse: Int, rnd: Random): IndexedSeq[Long] = {
    val records = span / word
    var launched = 1
    IndexedSeq.fill(n) {
      if (rnd.nextInt(reuse) == 0 && launched < records) launched += 1
      val r = launched - 1 - rnd.nextInt(window min launched)
      r.toLong * word
    }
  }
}
