package mapm.sim

import java.nio.charset.StandardCharsets.UTF_8
import java.nio.file.{Files, Path, Paths, StandardOpenOption}
import java.nio.file.attribute.FileTime
import java.util.concurrent.{CountDownLatch, Executors}
import java.util.concurrent.atomic.AtomicInteger

import scala.jdk.CollectionConverters._

import org.scalatest.funsuite.AnyFunSuite

/** The build cache that every spec and command shares: an entry is built once, whoever asks for it
  * and however many ask at once (threads of one JVM or separate processes), a changed input makes
  * a new entry, an incomplete or failed one is built again, and pruning drops the least recently
  * used entries first. */
class BuildCacheSpec extends AnyFunSuite {
  private def fresh(name: String, maxBytes: Long = Long.MaxValue): BuildCache = {
    val root = Paths.get("target/build-cache-test").resolve(name).toAbsolutePath
    AtomicDir.delete(root)
    new BuildCache(root, maxBytes)
  }
  private val hasFile = (d: Path) => Files.isRegularFile(d.resolve("out"))
  private def write(d: Path, text: String): Unit = Files.write(d.resolve("out"), text.getBytes(UTF_8))
  private def read(d: Path): String = new String(Files.readAllBytes(d.resolve("out")), UTF_8)

  test("built once for the same inputs, again for other inputs, anew when asked to rebuild") {
    val c = fresh("once")
    val fills = new AtomicInteger
    def get(parts: String*) = c.entry("k", "unit", parts, hasFile) { d => write(d, s"fill ${fills.incrementAndGet()}") }
    val a = get("v1", "flags")
    assert(get("v1", "flags") == a && read(a) == "fill 1" && fills.get == 1)
    val b = get("v2", "flags")
    assert(b != a && read(b) == "fill 2" && read(a) == "fill 1", "another input, another entry; the first kept")
    assert(b.getParent == c.root.resolve("k") && b.getFileName.toString.startsWith("unit-"))
    val r = c.entry("k", "unit", Seq("v1", "flags"), hasFile, rebuild = true) { d => write(d, "rebuilt") }
    assert(r == a && read(a) == "rebuilt")
  }

  test("an entry whose completion mark is missing is built again; a failed fill leaves no entry") {
    val c = fresh("incomplete")
    val d = c.dir("k", "unit", Seq("x"))
    Files.createDirectories(d) // a folder without its output, as an older version left half-built ones
    assert(read(c.entry("k", "unit", Seq("x"), hasFile)(write(_, "whole"))) == "whole")
    val e = intercept[IllegalStateException](c.entry("k", "bad", Seq("y"), hasFile) { t => write(t, "half"); throw new IllegalStateException("compiler died") })
    assert(e.getMessage == "compiler died")
    assert(!Files.exists(c.dir("k", "bad", Seq("y"))))
    assert(Files.list(c.root.resolve("k")).iterator.asScala.map(_.getFileName.toString).forall(n => !n.contains(".tmp-")), "no temporary folder left")
  }

  test("eight threads asking for one entry at once: one fill, every caller gets it whole") {
    val c = fresh("threads")
    val fills = new AtomicInteger
    val pool = Executors.newFixedThreadPool(8)
    val go = new CountDownLatch(1)
    val got = (0 until 8).map { i =>
      pool.submit[Path] { () =>
        go.await()
        c.entry("k", "unit", Seq("same"), hasFile) { d => fills.incrementAndGet(); Thread.sleep(100); write(d, s"thread $i") }
      }
    }
    go.countDown()
    val dirs = got.map(_.get)
    pool.shutdown()
    assert(fills.get == 1 && dirs.distinct.size == 1 && read(dirs.head).startsWith("thread "))
  }

  test("four processes asking for one entry at once: one fill (the file lock), all see it") {
    val c = fresh("processes")
    val log = c.root.resolveSibling("processes-fills.log")
    Files.deleteIfExists(log)
    val java = Paths.get(sys.props("java.home"), "bin", "java").toString
    val procs = (0 until 4).map { i =>
      new ProcessBuilder(java, "-cp", sys.props("java.class.path"), "mapm.sim.BuildCacheRacer", c.root.toString, log.toString, i.toString)
        .redirectErrorStream(true).start()
    }
    val outs = procs.map(p => new String(p.getInputStream.readAllBytes(), UTF_8).trim)
    assert(procs.map(_.waitFor()) == Seq.fill(4)(0), outs.mkString("\n"))
    val fills = Files.readAllLines(log).asScala.toSeq
    assert(fills.size == 1, s"fills: $fills")
    assert(outs.distinct.size == 1 && outs.head == s"process ${fills.head}", outs.mkString("\n"))
  }

  test("pruning past the limit removes the least recently used entries down to 80 %; a use renews an entry") {
    val c = fresh("prune")
    val kb = Array.fill[Byte](1024)(1)
    val names = (0 until 5).map(i => s"e$i")
    val dirs = names.map(n => c.entry("k", n, Seq(n), hasFile) { d => Files.write(d.resolve("out"), kb) })
    // Last used 10, 20, ... 50 minutes ago, then e0 (the oldest) used again now.
    for ((d, i) <- dirs.zipWithIndex) Files.setLastModifiedTime(d, FileTime.fromMillis(System.currentTimeMillis() - (50 - 10 * i) * 60000L))
    assert(c.entry("k", "e0", Seq("e0"), hasFile)(_ => fail("e0 is there")) == dirs(0))
    assert(c.prune(limit = 5 * 1024) == Seq.empty, "at the limit nothing goes")
    val removed = c.prune(limit = 4 * 1024)
    assert(removed == Seq(dirs(1), dirs(2)), "down to 80 % of 4 KiB: the two least recently used")
    assert(c.entries.map(_._1).toSet == Set(dirs(0), dirs(3), dirs(4)))
  }

  test("the key names the tools: Verilator, the C++ compiler, Chisel and firtool") {
    val v = BuildCache.toolVersions
    assert(Seq("verilator=", "cxx=", s"chisel=${chisel3.BuildInfo.version}", "firtool=").forall(v.contains), v)
  }
}

/** One racing process of [[BuildCacheSpec]]: asks for the entry, recording in the log (appended
  * under no lock of its own) when it fills it, and prints who filled the entry it got. */
object BuildCacheRacer {
  def main(args: Array[String]): Unit = {
    val Array(root, log, id) = args
    val c = new BuildCache(Paths.get(root), Long.MaxValue)
    val d = c.entry("k", "unit", Seq("same"), d => Files.isRegularFile(d.resolve("out"))) { d =>
      Files.write(Paths.get(log), s"$id\n".getBytes(UTF_8), StandardOpenOption.CREATE, StandardOpenOption.APPEND)
      Thread.sleep(500)
      Files.write(d.resolve("out"), id.getBytes(UTF_8))
    }
    println(s"process ${new String(Files.readAllBytes(d.resolve("out")), UTF_8)}")
  }
}
