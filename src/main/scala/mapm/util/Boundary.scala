package mapm.util

import chisel3.experimental.BaseModule

/** The parts whose boundary the design registers: no output may depend combinationally on an
  * input, configuration inputs (`io_cfg...`, held for a whole frame) aside. A module states it in
  * its constructor; the whole-configuration cost flow checks every part so tagged in the
  * synthesized netlist and fails on a path (docs/cost.md, "Paths between parts"). */
object Boundary {
  private val tags = new ModuleTags[Unit]

  /** States that module `m` (called in its constructor) has no input-to-output combinational path. */
  def registered(m: BaseModule): Unit = tags.tag(m, ())

  /** Runs `elaborate` and returns its result with the names of the modules that stated it. */
  def collect[R](elaborate: => R): (R, Set[String]) = { val (r, t) = tags.collect(elaborate); (r, t.keySet) }

  /** Whether a path from input port `port` counts: configuration inputs are static in a frame. */
  def counts(port: String): Boolean = !port.startsWith("io_cfg")
}
