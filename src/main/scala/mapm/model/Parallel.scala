package mapm.model

import mapm.numerics._

import scala.jdk.CollectionConverters._

/** Runs independent index ranges on worker threads: the one thread pool of the model. */
object Parallel {
  /** Default worker count: the machine's processors. */
  def defaultThreads: Int = Runtime.getRuntime.availableProcessors

  /** Splits [0, n) into chunks of `chunk` indices, taken in turn from a shared counter by up to
    * `threads` workers (a lone worker runs on the calling thread). Each worker first makes its own
    * state with `state`, then calls `body(state, from, until)` for every chunk it takes; the
    * states are returned (one per worker) for the caller to combine. `body` must write its
    * results into slots of its own; the first exception thrown by any worker is rethrown here.
    * `progress`, when given, advances by each finished chunk. */
  def forChunks[S](n: Int, threads: Int, chunk: Int, progress: Option[Progress] = None)(state: => S)(body: (S, Int, Int) => Unit): Seq[S] = {
    require(threads >= 1, s"threads must be >= 1, got $threads")
    require(chunk >= 1, s"chunk must be >= 1, got $chunk")
    val workers = math.max(1, math.min(threads, (n + chunk - 1) / chunk))
    val next = new java.util.concurrent.atomic.AtomicInteger(0)
    val failure = new java.util.concurrent.atomic.AtomicReference[Throwable](null)
    val states = new java.util.concurrent.ConcurrentLinkedQueue[S]()
    def work(): Unit = {
      val s = state
      states.add(s)
      var from = next.getAndAdd(chunk)
      while (from < n && failure.get == null) {
        val until = math.min(n, from + chunk)
        body(s, from, until)
        progress.foreach(_.advance((until - from).toLong))
        from = next.getAndAdd(chunk)
      }
    }
    if (workers == 1) work()
    else {
      val ts = Array.fill(workers)(new Thread(() => try work() catch { case t: Throwable => failure.compareAndSet(null, t) }))
      ts.foreach(_.start())
      ts.foreach(_.join())
      if (failure.get != null) throw failure.get
    }
    states.asScala.toSeq
  }

  /** Calls `body(i)` for every i in [0, n) on `threads` threads, in chunks as [[forChunks]]. */
  def forRange(n: Int, threads: Int, chunk: Int = 64, progress: Option[Progress] = None)(body: Int => Unit): Unit =
    forChunks(n, threads, chunk, progress)(()) { (_, from, until) =>
      var i = from
      while (i < until) { body(i); i += 1 }
    }
}
