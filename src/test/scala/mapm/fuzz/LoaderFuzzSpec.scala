package mapm.fuzz

import java.nio.file.{Files, Paths}

import mapm.MapmError
import org.scalatest.funsuite.AnyFunSuite

/** The loader fuzzer: its verdicts on known outcomes, the replay of an input from its seed and
  * index alone, and the CI's seeded sample (the benchmark, `mapm fuzz`, runs 100,000 inputs). */
class LoaderFuzzSpec extends AnyFunSuite {
  private val scenes = Paths.get("test-scenes/cornell-box")

  private def withFuzz[T](timeoutMs: Long)(f: LoaderFuzz => T): T = {
    val work = Files.createTempDirectory("fuzz-spec")
    val z = new LoaderFuzz(scenes, work, timeoutMs)
    try f(z) finally z.close()
  }

  test("only a load or a one-line MapmError is allowed; anything else is named") {
    withFuzz(500) { z =>
      assert(z.outcome(()) == Right(true))
      assert(z.outcome(MapmError.fail("x.obj:3: bad")) == Right(false))
      assert(z.outcome(MapmError.fail("two\nlines")).left.exists(_.contains("not one line")))
      assert(z.outcome(MapmError.fail("")).left.exists(_.contains("not one line")))
      assert(z.outcome(Vector.empty[Int](3)).left.exists(_.contains("IndexOutOfBoundsException")))
      assert(z.outcome(throw new OutOfMemoryError("Java heap space")).left.exists(_.contains("out of memory")))
      def deep(n: Int): Int = if (n == 0) 0 else 1 + deep(n - 1)
      assert(z.outcome(deep(100000000)) == Left("stack overflow"))
      assert(z.outcome(Thread.sleep(600000)).left.exists(_.contains("a hang"))) // interrupted when abandoned
      assert(z.outcome(()) == Right(true), "the next input runs on a fresh worker")
    }
  }

  test("an input is a function of the seed and its index alone") {
    withFuzz(10000) { z =>
      val a = (0 until 50).map(i => z.generate(7, i))
      val b = (0 until 50).map(i => z.generate(7, i))
      assert(a.zip(b).forall { case (x, y) => x.kind == y.kind && x.obj.sameElements(y.obj) && x.mtl.sameElements(y.mtl) && x.scene.sameElements(y.scene) })
      assert(a.map(_.kind).toSet.size >= 5, "the kinds are mixed")
      assert((0 until 50).map(i => z.generate(8, i).scene.toSeq) != a.map(_.scene.toSeq), "another seed, other inputs")
    }
  }

  test("a seeded sample of 3,000 inputs: every outcome a load or a one-line error") {
    val s = LoaderFuzz.run(scenes, seed = 20261203, from = 0, count = 3000, timeoutMs = 10000, keepDir = Paths.get("target/fuzz-spec-failures"))
    assert(s.failures.isEmpty, s.failures.take(5).mkString("\n"))
    assert(s.inputs == 3000 && s.loaded + s.rejected == 3000)
    assert(s.loaded > 50 && s.rejected > 1000, s"$s: both outcomes occur")
    assert(Set("obj", "mtl", "scene-json", "scene-text", "bytes", "truncated", "deep").subsetOf(s.byKind.keySet), s.byKind)
  }
}
