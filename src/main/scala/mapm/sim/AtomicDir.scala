package mapm.sim

import java.nio.file.{AtomicMoveNotSupportedException, FileSystemException, Files, Path, StandardCopyOption}

import scala.jdk.CollectionConverters._

/** Cache folders that several processes may fill at once: local sweep jobs, or Slurm array tasks
  * on a shared file system building the same configuration. A folder is filled under a private
  * sibling name and renamed into place in one step, so no process ever reads a half-written one;
  * when two race, the first rename wins and the loser's copy is deleted. */
object AtomicDir {
  /** `dir` when it exists; otherwise fills a private sibling with `fill` and renames it to `dir`. */
  def create(dir: Path)(fill: Path => Unit): Path = {
    if (Files.isDirectory(dir)) return dir
    Files.createDirectories(dir.getParent)
    val host = java.net.InetAddress.getLocalHost.getHostName.takeWhile(_ != '.')
    val tmp = dir.resolveSibling(s".${dir.getFileName}.tmp-$host-${ProcessHandle.current.pid}-${java.util.UUID.randomUUID.toString.take(8)}")
    Files.createDirectories(tmp)
    try {
      fill(tmp)
      try Files.move(tmp, dir, StandardCopyOption.ATOMIC_MOVE)
      catch {
        case e: AtomicMoveNotSupportedException => throw new java.io.IOException(s"$dir: the file system cannot rename folders atomically", e)
        // Another process finished first (rename(2) reports ENOTEMPTY or EEXIST): keep its copy.
        case _: FileSystemException if Files.isDirectory(dir) => delete(tmp)
      }
      dir
    } catch { case e: Throwable => delete(tmp); throw e }
  }

  /** Deletes a folder tree (nothing when it is absent). */
  def delete(dir: Path): Unit = if (Files.exists(dir))
    Files.walk(dir).iterator.asScala.toSeq.reverse.foreach(Files.deleteIfExists)
}
