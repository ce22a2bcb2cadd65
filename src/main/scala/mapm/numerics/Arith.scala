package mapm.numerics

/** The SOA's and TSA's arithmetic: the dissertation's digit-serial online units, or the
  * conventional parallel floating-point baseline it compared them with (section 4.2). */
sealed abstract class Arith(name: String) extends mapm.Choice(name)

object Arith extends mapm.Choices[Arith] {
  /** Online arithmetic: the SOA's digit-serial shader chain and the TSA's online comparators. */
  case object Online extends Arith("online")
  /** Conventional parallel floating point, every operation rounded to nearest even. */
  case object Conventional extends Arith("conventional")

  val all: Seq[Arith] = Seq(Online, Conventional)

  protected def unknown(s: String): String = s"arithmetic must be online or conventional, got '$s'"
}
