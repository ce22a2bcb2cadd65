package mapm

/** One of a sealed family of named choices (an arithmetic, a fidelity, a slot layout): its name is
  * what the command line, the file headers and the module names say. */
abstract class Choice(val name: String) {
  override def toString: String = name
}

/** The companion of a sealed family of [[Choice]]s: every member, and the member a name gives. */
abstract class Choices[T <: Choice] {
  /** Every member, in the order `--help` lists them. */
  def all: Seq[T]

  /** The one-line message for a name `s` that is no member's. */
  protected def unknown(s: String): String

  /** The member named `s`, or a [[MapmError]]. */
  def parse(s: String): T = all.find(_.name == s).getOrElse(MapmError.fail(unknown(s)))
}
