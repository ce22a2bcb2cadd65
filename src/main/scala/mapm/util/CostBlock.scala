package mapm.util

import chisel3.experimental.BaseModule

/** A block of the cost report (docs/cost.md): every synthesized module's cells count in the block
  * of its nearest tagged ancestor (itself included). */
sealed abstract class CostBlock(name: String) extends mapm.Choice(name)

object CostBlock {
  case object TsBlock extends CostBlock("TS block")
  case object SoBlock extends CostBlock("SO block")
  case object Uncore extends CostBlock("uncore")
  case object Caches extends CostBlock("caches")
  case object Top extends CostBlock("top")
  /** The coprocessor around the MAPM (mapm.soc): registers, stream reader, frame accumulator and
    * writer, the AXI4 bridge and checker. */
  case object Coproc extends CostBlock("coprocessor")
  /** The blocks in report order. */
  val all: Seq[CostBlock] = Seq(TsBlock, SoBlock, Uncore, Caches, Top, Coproc)

  private val tags = new ModuleTags[CostBlock]

  /** Tags module `m` (called in its constructor) with `block`, when an elaboration collects tags. */
  def tag(m: BaseModule, block: CostBlock): Unit = tags.tag(m, block)

  /** Runs `elaborate` (which elaborates a design) and returns its result with the blocks the
    * design's modules were tagged with, by module name. */
  def collect[T](elaborate: => T): (T, Map[String, CostBlock]) = tags.collect(elaborate)

  /** The block of the module at the end of `chain` (module names from the top down): its nearest
    * tagged ancestor's. A module whose only tagged ancestor is the top, though it is not the top,
    * has no block: the answer is `Left` with a message naming it, so that a new module's area
    * cannot silently count as the top's. */
  def of(chain: Seq[String], tags: Map[String, CostBlock]): Either[String, CostBlock] = {
    val tagged = chain.indices.reverse.find(i => tags.contains(chain(i)))
    tagged match {
      case Some(i) if i > 0 || chain.size == 1 => Right(tags(chain(i)))
      case _ => Left(s"module ${chain.last} (${chain.mkString(" / ")}) has no cost block: tag it or a module above it with CostBlock.tag")
    }
  }
}
