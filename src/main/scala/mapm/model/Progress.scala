package mapm.model

/** A progress bar on stderr for stages that take more than a second.
  *
  * Nothing is drawn for the first second, nor when stderr is not a terminal unless
  * MAPM_PROGRESS=1; MAPM_PROGRESS=0 turns it off. Thread-safe: workers call [[advance]].
  */
final class Progress(label: String, total0: Long) {
  @volatile private var total = total0
  private val start = System.nanoTime()
  private val done = new java.util.concurrent.atomic.AtomicLong(0)
  @volatile private var lastDraw = 0L
  @volatile private var drawn = false
  private val enabled: Boolean = sys.env.get("MAPM_PROGRESS") match {
    case Some("0") => false
    case Some("1") => true
    case _         => System.console() != null
  }

  def advance(n: Long = 1): Unit = {
    val d = done.addAndGet(n)
    if (enabled) {
      val now = System.nanoTime()
      if (now - start > 1000000000L && now - lastDraw > 200000000L) synchronized {
        if (now - lastDraw > 200000000L) { lastDraw = now; draw(d, now) }
      }
    }
  }

  private def draw(d: Long, now: Long): Unit = {
    val frac = if (total <= 0) 1.0 else math.min(1.0, d.toDouble / total)
    val width = 30
    val bar = "#" * (frac * width).toInt + "." * (width - (frac * width).toInt)
    val secs = (now - start) / 1e9
    System.err.print(f"\r$label [$bar] ${frac * 100}%5.1f%% ($d/$total) $secs%.1fs ")
    drawn = true
  }

  /** Raises the total by `n` steps, for a stage whose size shows as it goes. */
  def extend(n: Long): Unit = synchronized { total += n }

  /** Ends the bar (a final full line if one was drawn). */
  def finish(): Unit = if (drawn) synchronized { draw(done.get, System.nanoTime()); System.err.println() }
}

object Progress {
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
