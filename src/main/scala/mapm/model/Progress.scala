package mapm.model

import mapm.numerics._

import me.tongfei.progressbar.{ConsoleProgressBarConsumer, ProgressBar, ProgressBarBuilder, ProgressBarConsumer, ProgressBarStyle}

/** A progress bar on stderr for stages that take more than a second, drawn by the progressbar
  * library (me.tongfei:progressbar) as one plain ASCII line redrawn in place.
  *
  * It draws only when stderr is a terminal, or when MAPM_PROGRESS=1; MAPM_PROGRESS=0 turns it
  * off. When off, no bar (and no refresh thread) exists. Nothing is drawn in the first second, so
  * a short stage leaves no line. Thread-safe: workers call [[advance]].
  */
final class Progress(label: String, total: Long) {
  private val bar: Option[ProgressBar] =
    if (!Progress.enabled) None
    else Some(new ProgressBarBuilder().setTaskName(label).setInitialMax(total).setStyle(ProgressBarStyle.ASCII)
      .setUpdateIntervalMillis(Progress.RefreshMillis).setConsumer(new Progress.AfterOneSecond).build())

  /** Counts `n` more steps done. */
  def advance(n: Long = 1): Unit = bar.foreach(_.stepBy(n))

  /** Raises the total by `n` steps, for a stage whose size shows as it goes. */
  def extend(n: Long): Unit = bar.foreach(b => b.synchronized(b.maxHint(b.getMax + n)))

  /** Ends the bar (a final full line if one was drawn). */
  def finish(): Unit = bar.foreach(_.close())
}

object Progress {
  private val RefreshMillis = 200
  /** Characters of a drawn line: the library then needs no terminal query for the width. */
  private val LineWidth = 100

  /** Whether bars are drawn (stderr a terminal, or MAPM_PROGRESS=1; never with MAPM_PROGRESS=0). */
  def drawn: Boolean = enabled

  private def enabled: Boolean = sys.env.get("MAPM_PROGRESS") match {
    case Some("0") => false
    case Some("1") => true
    case _         => System.console() != null
  }

  /** The library's plain console consumer (`\r` and the line on stderr), silent until a second
    * has passed; the closing newline only follows a drawn line. */
  private final class AfterOneSecond extends ProgressBarConsumer {
    private val console = new ConsoleProgressBarConsumer(System.err, LineWidth)
    private val start = System.nanoTime()
    @volatile private var drawn = false
    def getMaxRenderedLength: Int = console.getMaxRenderedLength
    def accept(line: String): Unit =
      if (drawn || System.nanoTime() - start > 1000000000L) { drawn = true; console.accept(line) }
    def close(): Unit = if (drawn) console.close()
  }

  /** Runs `body` with a bar over `total` steps and finishes it. */
  def apply[T](label: String, total: Long)(body: Progress => T): T = {
    val p = new Progress(label, total)
    try body(p) finally p.finish()
  }

  /** Runs `body` with a bar over `total` steps when `label` is given (None otherwise), and
    * finishes it. */
  def maybe[T](label: Option[String], total: Long)(body: Option[Progress] => T): T = {
    val p = label.map(new Progress(_, total))
    try body(p) finally p.foreach(_.finish())
  }
}
