package mapm.sim

import java.nio.file.{Files, Paths}
import java.util.concurrent.{CountDownLatch, Executors}

import scala.jdk.CollectionConverters._

import org.scalatest.funsuite.AnyFunSuite

/** Concurrent fills of one cache folder (as two Slurm tasks building one configuration): each
  * caller gets the folder whole, one fill wins, nothing half-written or temporary is left. */
class AtomicDirSpec extends AnyFunSuite {
  test("eight racing fills of one folder: one complete copy, no temporary folders left") {
    val base = Paths.get("target/atomic-dir-test")
    AtomicDir.delete(base)
    val dir = base.resolve("build")
    val pool = Executors.newFixedThreadPool(8)
    val go = new CountDownLatch(1)
    val results = (0 until 8).map { i =>
      pool.submit[java.nio.file.Path] { () =>
        go.await()
        AtomicDir.create(dir) { tmp =>
          for (k <- 0 until 20) Files.write(tmp.resolve(s"part-$k"), s"$i".getBytes("UTF-8")) // one writer's files only
          Thread.sleep(20)
        }
      }
    }
    go.countDown()
    assert(results.map(_.get) == Seq.fill(8)(dir))
    pool.shutdown()
    val parts = Files.list(dir).iterator.asScala.toSeq
    assert(parts.size == 20)
    assert(parts.map(p => new String(Files.readAllBytes(p), "UTF-8")).distinct.size == 1, "every file from the same fill")
    assert(Files.list(base).iterator.asScala.map(_.getFileName.toString).toSeq == Seq("build"), "no temporary folder left")
  }

  test("a fill that fails leaves nothing behind and the error goes to the caller") {
    val base = Paths.get("target/atomic-dir-test-fail")
    AtomicDir.delete(base)
    val e = intercept[IllegalStateException](AtomicDir.create(base.resolve("x")) { tmp =>
      Files.write(tmp.resolve("half"), Array[Byte](1)); throw new IllegalStateException("compiler died") })
    assert(e.getMessage == "compiler died")
    assert(Files.list(base).iterator.asScala.isEmpty)
  }
}
