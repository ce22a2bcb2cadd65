package mapm.sim

import java.nio.channels.FileChannel
import java.nio.file.{Files, Path, Paths, StandardOpenOption}
import java.nio.file.attribute.FileTime
import java.util.concurrent.ConcurrentHashMap
import java.util.concurrent.locks.ReentrantLock

import scala.jdk.CollectionConverters._
import scala.util.Try

/** The one content-addressed cache of what the project builds from its sources: emitted
  * SystemVerilog of whole MAPMs, Verilator harness and pipe executables, synthesized netlists and
  * the cost flow's unit figures. Every command, spec and checkout on a machine shares it, so a design is built once
  * per machine, not once per spec, per run or per clone (docs/testing.md).
  *
  * An entry is the folder `<root>/<kind>/<name>-<hash>`. The hash covers everything the result
  * depends on: the caller's inputs (Verilog text, harness sources, parameters, flags) and
  * [[BuildCache.toolVersions]] (Verilator, the C++ compiler, Chisel and firtool), so a changed source or tool
  * makes a new entry rather than reusing a stale one. An entry is filled under a private name and
  * renamed into place ([[AtomicDir]]) while holding a lock (a lock within this JVM and a file lock
  * for other processes), so concurrent builders of one entry build it once: the others wait and
  * reuse it. Each use marks its entry; after a new entry, [[prune]] removes the least recently
  * used ones once the cache passes `maxBytes`.
  *
  * [[BuildCache.default]] is the machine's cache, under `$MAPM_CACHE/builds` when `MAPM_CACHE` is
  * set (tools/setup.sh keeps its tools in the same folder), else `~/.cache/mapm/builds`, pruned
  * past `MAPM_CACHE_MAX_GB` (default 20 GB); `rm -rf` of it is always safe. */
final class BuildCache(val root: Path, val maxBytes: Long) {
  /** The entry folder of `name` under `kind` for the inputs `parts`. */
  def dir(kind: String, name: String, parts: Seq[String]): Path =
    root.resolve(kind).resolve(s"$name-${Verilator.hash(BuildCache.toolVersions +: parts: _*)}")

  /** The entry of `name` under `kind` for the inputs `parts`: when `complete` holds for it, as it
    * is; otherwise (or when `rebuild`) made anew by `fill`, which writes into the folder it is
    * given. Concurrent callers for the same entry, in this JVM or in other processes, build it
    * once. Returns the entry's folder. */
  def entry(kind: String, name: String, parts: Seq[String], complete: Path => Boolean, rebuild: Boolean = false)(
      fill: Path => Unit): Path = {
    val d = dir(kind, name, parts)
    if (!rebuild && complete(d)) { touch(d); return d }
    val made = locked(d) {
      if (rebuild || !complete(d)) {
        AtomicDir.delete(d) // an older entry that stopped half-way, or one to rebuild
        AtomicDir.create(d)(fill)
        true
      } else false
    }
    touch(d)
    if (made) prune()
    d
  }

  /** Marks an entry as used now (its folder's modification time orders [[prune]]). */
  private def touch(d: Path): Unit = Try(Files.setLastModifiedTime(d, FileTime.fromMillis(System.currentTimeMillis())))

  /** Runs `body` holding the lock of entry `d`: a lock within this JVM (file locks are per
    * process) and a file lock beside the entry for other processes. Where the file system refuses
    * file locks, AtomicDir alone keeps concurrent builders apart (each builds; one copy is kept). */
  private def locked[T](d: Path)(body: => T): T = {
    val jvm = BuildCache.jvmLocks.computeIfAbsent(d, _ => new ReentrantLock)
    jvm.lock()
    try {
      Files.createDirectories(d.getParent)
      val lockFile = d.resolveSibling(s".${d.getFileName}.lock")
      val channel = Try(FileChannel.open(lockFile, StandardOpenOption.CREATE, StandardOpenOption.WRITE)).toOption
      val lock = channel.flatMap(c => Try(c.lock()).toOption)
      try body
      finally { lock.foreach(l => Try(l.release())); channel.foreach(c => Try(c.close())) }
    } finally jvm.unlock()
  }

  /** The entries as (folder, last use in ms, bytes), least recently used first. */
  def entries: Seq[(Path, Long, Long)] = {
    if (!Files.isDirectory(root)) return Seq.empty
    val kinds = Files.list(root).iterator.asScala.filter(Files.isDirectory(_)).toSeq
    kinds.flatMap(k => Files.list(k).iterator.asScala.filter(p => Files.isDirectory(p) && !p.getFileName.toString.startsWith(".")).toSeq)
      .map(e => (e, Try(Files.getLastModifiedTime(e).toMillis).getOrElse(0L), BuildCache.size(e))).sortBy(_._2)
  }

  /** When the cache holds more than `limit` bytes, removes the least recently used entries until
    * it holds at most 80 % of it. Returns the folders removed. */
  def prune(limit: Long = maxBytes): Seq[Path] = {
    val all = entries
    var total = all.map(_._3).sum
    if (total <= limit) return Seq.empty
    val removed = Seq.newBuilder[Path]
    for ((e, _, bytes) <- all if total > limit * 8 / 10) {
      Try(AtomicDir.delete(e)).foreach { _ => total -= bytes; removed += e }
    }
    removed.result()
  }
}

object BuildCache {
  /** The machine's cache: `$MAPM_CACHE/builds` (tools/setup.sh keeps its tools in `$MAPM_CACHE`),
    * else `~/.cache/mapm/builds`, pruned past `MAPM_CACHE_MAX_GB` (default 20). */
  lazy val default: BuildCache = {
    val base = sys.env.get("MAPM_CACHE").filter(_.nonEmpty).map(Paths.get(_))
      .getOrElse(Paths.get(sys.props("user.home"), ".cache", "mapm"))
    val gb = sys.env.get("MAPM_CACHE_MAX_GB").flatMap(s => Try(s.toDouble).toOption).filter(_ > 0).getOrElse(20.0)
    new BuildCache(base.resolve("builds").toAbsolutePath, (gb * (1L << 30)).toLong)
  }

  /** The machine cache's root folder. */
  def root: Path = default.root

  /** [[BuildCache.entry]] of the machine's cache. */
  def entry(kind: String, name: String, parts: Seq[String], complete: Path => Boolean, rebuild: Boolean = false)(
      fill: Path => Unit): Path = default.entry(kind, name, parts, complete, rebuild)(fill)

  /** The versions of the tools that turn sources into cached results, part of every key: a
    * Verilator or compiler upgrade rebuilds. A tool that is absent reads as "none". */
  lazy val toolVersions: String = {
    def out(cmd: String*): String = Try(scala.sys.process.Process(cmd).!!.trim).getOrElse("none")
    val verilator = mapm.SetupScript.which("verilator").map(v => out(v.toString, "--version")).getOrElse("none")
    val cxx = out(sys.env.getOrElse("CXX", "g++"), "--version").linesIterator.take(1).mkString
    s"verilator=$verilator cxx=$cxx chisel=${chisel3.BuildInfo.version} firtool=${chisel3.BuildInfo.firtoolVersion.getOrElse("none")}"
  }

  private val jvmLocks = new ConcurrentHashMap[Path, ReentrantLock]

  private def size(p: Path): Long =
    Try(Files.walk(p).iterator.asScala.filter(Files.isRegularFile(_)).map(f => Try(Files.size(f)).getOrElse(0L)).sum).getOrElse(0L)
}
