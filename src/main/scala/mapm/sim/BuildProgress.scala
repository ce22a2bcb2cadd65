package mapm.sim

import java.nio.file.{Files, Path}
import java.util.concurrent.{Executors, ScheduledFuture, TimeUnit}

import scala.jdk.CollectionConverters._

import mapm.model.Progress

/** The progress of one Verilator build (`verilator --build`), read from its output as it runs:
  * first Verilator itself (verilating), then make compiling the C++ files one by one (each a
  * `-c -o` line; how many there are is read from the Makefiles Verilator wrote, see [[units]]),
  * then the link. On a terminal the compile shows as a bar of files done; otherwise, and while
  * Verilator itself runs, `log` gets a status line every `everyMillis` (30 s by default), so a
  * build of minutes is never silent. Thread-safe: [[line]] is called from the process's reader. */
final class BuildProgress(label: String, obj: Path, top: String, log: String => Unit, everyMillis: Long = 30000) {
  private val t0 = System.nanoTime()
  @volatile private var total: Option[Int] = None
  @volatile private var compiled = 0
  @volatile private var bar: Option[Progress] = None
  private val ticker: ScheduledFuture[_] =
    BuildProgress.timer.scheduleAtFixedRate(() => if (bar.isEmpty) log(s"$label: $status"), everyMillis, everyMillis, TimeUnit.MILLISECONDS)

  /** Takes one line of the build's output. */
  def line(l: String): Unit = synchronized {
    if (l.contains(" -c -o ")) {
      if (total.isEmpty) {
        total = Some(BuildProgress.units(obj, top).max(1))
        if (Progress.drawn) bar = Some(new Progress(s"$label: C++ files", total.get.toLong))
      }
      compiled += 1
      bar.foreach(_.advance())
    }
  }

  /** Where the build is, for a status line: verilating, compiling k of n files, or linking. */
  def status: String = {
    val secs = (System.nanoTime() - t0) / 1000000000L
    total match {
      case None                     => s"verilating ($secs s so far)"
      case Some(n) if compiled >= n => s"linking ($secs s so far)"
      case Some(n)                  => s"compiled $compiled of $n C++ files ($secs s so far)"
    }
  }

  /** Ends the ticker and the bar. */
  def close(): Unit = synchronized {
    ticker.cancel(false)
    bar.foreach(_.finish())
    bar = None
  }
}

object BuildProgress {
  private lazy val timer = Executors.newSingleThreadScheduledExecutor { (r: Runnable) =>
    val t = new Thread(r, "mapm-build-progress"); t.setDaemon(true); t
  }

  /** The C++ files make compiles for `top` in the Verilator output folder `obj`, from the lists of
    * `V<top>_classes.mk` and `V<top>.mk` (Verilator 5 writes both before make starts): the
    * generated classes and support files, each its own file when `VM_PARALLEL_BUILDS` is 1, else
    * one `__ALL` file together; the run-time library's global files; the user's files (the
    * harness). 0 when the Makefiles cannot be read. */
  def units(obj: Path, top: String): Int = {
    def lines(f: Path) = if (Files.isRegularFile(f)) Files.readAllLines(f).asScala.toSeq.map(_.trim) else Seq.empty
    val files = Seq(lines(obj.resolve(s"V${top}_classes.mk")), lines(obj.resolve(s"V$top.mk")))
    val all = files.flatten
    // The entries of the list `v` (`v += \` or `v = \`, one entry a line up to a blank line).
    def entries(v: String): Int = files.map { ls =>
      val start = ls.indexWhere(t => (t.startsWith(v + " ") || t.startsWith(v + "=")) && t.endsWith("\\"))
      if (start < 0) 0 else ls.drop(start + 1).takeWhile(t => t.nonEmpty && t.endsWith("\\") && !t.contains("=")).size
    }.sum
    val generated = Seq("VM_CLASSES_FAST", "VM_CLASSES_SLOW", "VM_SUPPORT_FAST", "VM_SUPPORT_SLOW").map(entries).sum
    val parallel = !all.contains("VM_PARALLEL_BUILDS = 0")
    (if (parallel) generated else generated.min(1)) + Seq("VM_GLOBAL_FAST", "VM_GLOBAL_SLOW", "VM_USER_CLASSES").map(entries).sum
  }
}
