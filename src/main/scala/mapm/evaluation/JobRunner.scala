package mapm.evaluation

import java.util.concurrent.Executors

import scala.concurrent.{Await, ExecutionContext, Future}
import scala.concurrent.duration.Duration
import scala.util.{Failure, Try}

/** The one runner of `sweep`'s and `evaluate`'s local jobs: a pool of `threads` threads that
  * takes the jobs in the order given. */
object JobRunner {
  /** Runs `body` on each of `jobs`, at most `threads` at once, starting them in the order given.
    * With `deadline` (a `System.nanoTime` instant) a job not started by then is skipped. Waits
    * for every job that started; when any of them threw, rethrows the first (in the jobs' order)
    * after all have ended. Returns the jobs that ran. */
  def run[J](jobs: Seq[J], threads: Int, deadline: Option[Long] = None)(body: J => Unit): Seq[J] = {
    require(threads >= 1, s"job runner: threads must be at least 1, got $threads")
    if (jobs.isEmpty) return Seq.empty
    val pool = Executors.newFixedThreadPool(math.min(threads, jobs.size))
    implicit val ec: ExecutionContext = ExecutionContext.fromExecutorService(pool)
    try {
      val runs = jobs.map(j => Future(if (deadline.exists(System.nanoTime() > _)) false else { body(j); true }))
      val ended = runs.map(f => Try(Await.result(f, Duration.Inf)))
      ended.collectFirst { case Failure(e) => throw e }
      jobs.zip(ended).collect { case (j, scala.util.Success(true)) => j }
    } finally pool.shutdown()
  }
}
