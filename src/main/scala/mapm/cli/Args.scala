package mapm.cli

import mainargs.{ParserForClass, ParserForMethods, TokensReader}
import mapm.MapmError
import mapm.format.SlotLayout
import mapm.model.FloatFormat

/** Helpers shared by the commands: running a mainargs parser with our error convention, and
  * token readers for the project's own argument types. */
object Args {
  /** Parses `args` for the single `@main` method of `container` and runs it. A parse error
    * (unknown flag, bad value) becomes a [[MapmError]]; `--help` prints the usage. */
  def run[B](container: ParserForMethods[B], args: Seq[String], name: String, folders: Set[String] = Set("--out"),
             files: Set[String] = Set("--wave")): Int = {
    val help = helpText(container)
    if (args.contains("--help") || args.contains("-h")) {
      println(help)
      return 0
    }
    // An option the command does not take, named with the nearest one it does: the options are
    // read from the help text, the parser's own list.
    val known = """--[a-z0-9][a-z0-9-]*""".r.findAllIn(help).toSet
    for (bad <- args.filter(_.startsWith("--")).map(_.takeWhile(_ != '=')).find(a => !known(a)))
      MapmError.fail(s"$name: unknown option $bad${nearest(bad, known).fold("")(g => s" (did you mean $g?)")} (mapm $name --help lists the options)")
    checkOutputs(args, folders, files)
    container.runRaw(args, allowPositional = false, allowRepeats = false, nameMapper = mainargs.Util.kebabCaseNameMapper) match {
      case mainargs.Result.Success(code: Int)         => code
      case mainargs.Result.Success(_)                 => 0
      case mainargs.Result.Failure.Exception(t)       => throw t
      case _ =>
        // Not a run: a parse error. Render mainargs' own message (parsing again invokes nothing).
        // Its reason, without the signature it appends (the help prints that whole).
        val msg = container.runEither(args, allowPositional = false, allowRepeats = false).left.getOrElse("")
        val reason = msg.linesIterator.map(_.trim).filter(_.nonEmpty).takeWhile(!_.startsWith("Expected Signature")).mkString(" ")
        MapmError.fail(s"$name: ${if (reason.nonEmpty) reason else "bad arguments"} (mapm $name --help lists the options)")
    }
  }

  /** The usage `--help` prints. */
  def helpText[B](container: ParserForMethods[B]): String =
    container.helpText(totalWidth = 100, docsOnNewLine = false, customNames = Map.empty, customDocs = Map.empty, sorted = true,
      nameMapper = mainargs.Util.kebabCaseNameMapper).replace("mapm.cli.", "")

  /** The option among `known` nearest to the mistyped `bad`: one it starts, or one within a third of
    * its letters (at least 2) in edit distance; none when nothing is that close. */
  def nearest(bad: String, known: Set[String]): Option[String] = {
    def distance(a: String, b: String): Int = {
      val d = Array.tabulate(a.length + 1, b.length + 1)((i, j) => if (i == 0) j else if (j == 0) i else 0)
      for (i <- 1 to a.length; j <- 1 to b.length)
        d(i)(j) = Seq(d(i - 1)(j) + 1, d(i)(j - 1) + 1, d(i - 1)(j - 1) + (if (a(i - 1) == b(j - 1)) 0 else 1)).min
      d(a.length)(b.length)
    }
    val prefixed = known.filter(_.startsWith(bad)).toSeq
    if (prefixed.size == 1) return prefixed.headOption
    val (best, dist) = known.toSeq.sorted.map(k => k -> distance(bad, k)).minByOption(_._2).getOrElse(("", Int.MaxValue))
    if (dist <= math.max(2, (bad.length - 2) / 3)) Some(best) else None
  }

  /** Makes every output folder named by an option in `folders` and the folder of every output file
    * named by one in `files`, before any work: a path that cannot be made or written is a one-line
    * [[MapmError]] naming the option, not a failure at the end of a long run. */
  def checkOutputs(args: Seq[String], folders: Set[String], files: Set[String]): Unit =
    for (Seq(opt, value) <- args.sliding(2) if folders(opt) || files(opt)) {
      val path = java.nio.file.Paths.get(value).toAbsolutePath
      val dir = if (folders(opt)) path else path.getParent
      try java.nio.file.Files.createDirectories(dir)
      catch { case e: java.io.IOException => MapmError.fail(s"$opt $value: cannot create the folder $dir (${e.getClass.getSimpleName})") }
      MapmError.check(java.nio.file.Files.isWritable(dir), s"$opt $value: the folder $dir is not writable")
    }

  /** A seed must be a non-negative 64-bit number (the harness reads it unsigned). */
  def checkSeed(seed: Long, option: String = "--seed"): Unit =
    MapmError.check(seed >= 0, s"$option must be 0..${Long.MaxValue}, got $seed")

  implicit object FloatFormatReader extends TokensReader.Simple[FloatFormat] {
    def shortName = "format"
    def read(strs: Seq[String]): Either[String, FloatFormat] =
      try Right(FloatFormat.parse(strs.last))
      catch { case e: MapmError => Left(e.getMessage) }
  }

  implicit object ArithReader extends TokensReader.Simple[mapm.model.Arith] {
    def shortName = "arith"
    def read(strs: Seq[String]): Either[String, mapm.model.Arith] =
      try Right(mapm.model.Arith.parse(strs.last))
      catch { case e: MapmError => Left(e.getMessage) }
  }

  implicit object FidelityReader extends TokensReader.Simple[mapm.params.Fidelity] {
    def shortName = "fidelity"
    def read(strs: Seq[String]): Either[String, mapm.params.Fidelity] =
      try Right(mapm.params.Fidelity.parse(strs.last))
      catch { case e: MapmError => Left(e.getMessage) }
  }

  implicit object SlotLayoutReader extends TokensReader.Simple[SlotLayout] {
    def shortName = "layout"
    def read(strs: Seq[String]): Either[String, SlotLayout] =
      try Right(SlotLayout.parse(strs.last))
      catch { case e: MapmError => Left(e.getMessage) }
  }

  implicit object CacheSpecReader extends TokensReader.Simple[mapm.params.CacheSpec] {
    def shortName = "geometry"
    def read(strs: Seq[String]): Either[String, mapm.params.CacheSpec] =
      try Right(mapm.params.CacheSpec.parse(strs.last))
      catch { case e: MapmError => Left(e.getMessage) }
  }

  /** The hardware sizes `emit`, `render`, `sweep` and `evaluate` share (see [[rtlOptionsParser]] for why here). */
  implicit lazy val hwOptionsParser: ParserForClass[HwOptions] = ParserForClass[HwOptions]

  /** The parser of the options `render` and `sweep` share. It lives here, not in the options'
    * companion: mainargs finds a case class's defaults among its companion's members, which are
    * not all known while the companion itself is being compiled (every default was lost). */
  implicit lazy val rtlOptionsParser: ParserForClass[RtlOptions] = ParserForClass[RtlOptions]
}
