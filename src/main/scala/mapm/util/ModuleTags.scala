package mapm.util

import chisel3.experimental.BaseModule
import scala.collection.mutable.ArrayBuffer
import scala.util.DynamicVariable

/** Facts a module states about itself while it elaborates (its cost block, that its boundary is
  * registered), gathered by module name when an elaboration asks for them and ignored otherwise. */
final class ModuleTags[T] {
  private val registry = new DynamicVariable[Option[ArrayBuffer[(BaseModule, T)]]](None)

  /** Tags module `m` (called in its constructor) with `t`, when an elaboration collects tags. */
  def tag(m: BaseModule, t: T): Unit = registry.value.foreach(_ += m -> t)

  /** Runs `elaborate` (which elaborates a design) and returns its result with the tags the
    * design's modules got, by module name. */
  def collect[R](elaborate: => R): (R, Map[String, T]) = {
    val tags = ArrayBuffer.empty[(BaseModule, T)]
    val result = registry.withValue(Some(tags))(elaborate)
    (result, tags.map { case (m, t) => m.name -> t }.toMap)
  }
}
