package mapm.pipeline

/** Process CPU time, for benchmarks that report what a run got when other processes share the
  * cores. None where the JVM does not expose it. */
object ProcessCpu {
  private val bean: Option[com.sun.management.OperatingSystemMXBean] =
    java.lang.management.ManagementFactory.getOperatingSystemMXBean match {
      case o: com.sun.management.OperatingSystemMXBean => Some(o)
      case _                                           => None
    }

  /** CPU seconds this process has used so far (every thread, JIT and GC included). */
  def seconds: Option[Double] = bean.map(_.getProcessCpuTime / 1e9)

  /** CPU seconds used since `start` (a reading of [[seconds]]). */
  def since(start: Option[Double]): Option[Double] = for (a <- start; b <- seconds) yield b - a
}
