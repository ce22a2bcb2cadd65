package mapm

/** A user-facing error: bad input, impossible parameters, missing files.
  *
  * The CLI prints `mapm: <message>` on one line and exits non-zero; no stack trace. Code that
  * validates input throws this (through [[MapmError.fail]]) instead of a bare exception, so the
  * message names the file or the parameter and what is wrong with it.
  */
final class MapmError(message: String) extends RuntimeException(message)

object MapmError {
  /** Throws a [[MapmError]] with the given one-line message. */
  def fail(message: String): Nothing = throw new MapmError(message)

  /** Throws unless `cond` holds. */
  def check(cond: Boolean, message: => String): Unit = if (!cond) fail(message)
}
