package mapm.evaluation

import java.util.concurrent.atomic.AtomicInteger

import org.scalatest.funsuite.AnyFunSuite

/** The one runner of sweep's and evaluate's local jobs: every job once, never more than its
  * threads at once, none started after the deadline, and a failure reported after the rest ended. */
class JobRunnerSpec extends AnyFunSuite {
  test("every job runs once, at most `threads` at a time") {
    for (threads <- Seq(1, 2, 3, 8)) {
      val (now, peak) = (new AtomicInteger, new AtomicInteger)
      val seen = new java.util.concurrent.ConcurrentLinkedQueue[Int]
      val ran = JobRunner.run(0 until 20, threads) { j =>
        peak.accumulateAndGet(now.incrementAndGet(), math.max)
        Thread.sleep(5)
        seen.add(j)
        now.decrementAndGet()
      }
      assert(ran == (0 until 20))
      assert(seen.toArray.toSeq.map(_.asInstanceOf[Int]).sorted == (0 until 20))
      assert(peak.get >= 1 && peak.get <= threads, s"$threads threads, ${peak.get} at once")
    }
  }

  test("no job starts after the deadline; the ones that ran are returned") {
    // Job 2 outlasts the deadline by far (the first jobs start at once, far inside it).
    val ran = JobRunner.run(0 until 10, 1, deadline = Some(System.nanoTime() + 2000L * 1000000)) { j => if (j == 2) Thread.sleep(3000) }
    assert(ran == Seq(0, 1, 2), ran)
    assert(JobRunner.run(0 until 4, 2, deadline = Some(System.nanoTime() - 1))(_ => fail("ran after the deadline")).isEmpty)
  }

  test("a failing job: the others still run to the end, then its exception is thrown") {
    val done = new AtomicInteger
    val e = intercept[IllegalStateException](JobRunner.run(0 until 6, 2) { j =>
      if (j == 1) throw new IllegalStateException("job 1")
      Thread.sleep(20); done.incrementAndGet()
    })
    assert(e.getMessage == "job 1" && done.get == 5)
    assert(JobRunner.run(Seq.empty[Int], 4)(_ => fail("no job")).isEmpty)
  }
}
