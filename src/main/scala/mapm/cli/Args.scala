package mapm.cli

import mainargs.{ArgSig, ParserForClass, ParserForMethods, TokensReader}
import mapm.MapmError
import mapm.format.SlotLayout
import mapm.numerics.FloatFormat
import mapm.params.{CacheParams, MapmParams}

/** Helpers shared by the commands: running a mainargs parser with our error convention, and
  * token readers for the project's own argument types. */
object Args {
  /** Parses `args` for the single `@main` method of `cmd`'s parser and runs it. A parse error
    * (unknown flag, bad value) becomes a [[MapmError]]; `--help` prints the usage ([[helpText]]
    * of [[Command.options]]). The options in `folders` name output folders and those in `files`
    * output files, made (or refused) before any work ([[checkOutputs]]). */
  def run(cmd: Command, args: Seq[String], folders: Set[String] = Set("--out"), files: Set[String] = Set("--wave")): Int = {
    val container = cmd.parser
    val (name, opts) = (cmd.name, cmd.options)
    if (args.contains("--help") || args.contains("-h")) {
      println(helpText(name, opts))
      return 0
    }
    // An option the command does not take, named with the nearest one it does.
    val known = opts.flatMap(o => o.name +: o.short.map(c => s"-$c").toSeq).toSet
    for (bad <- args.filter(_.startsWith("-")).filterNot(_.matches("-[0-9.].*")).map(_.takeWhile(_ != '=')).find(a => !known(a)))
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

  /** One option as a command's parser defines it: `--name`, its one-letter form, the type of its
    * value (None for a flag), its doc, and its default: the value itself (None when the option
    * has none) and the text `--help` shows (None for a flag or an option that must be given). */
  final case class Opt(name: String, short: Option[Char], valueType: Option[String], doc: String, defaultValue: Option[Any],
                       defaultText: Option[String], reader: TokensReader[_]) {
    /** A value option with no default: the command needs it. */
    def required: Boolean = valueType.isDefined && defaultValue.isEmpty
  }

  /** The values a value type accepts, from the parsers of those types, for the help. */
  lazy val choices: Map[String, String] =
    Seq(FloatFormatReader, ArithReader, FidelityReader, SlotLayoutReader, QueryOrderReader, CacheSpecReader, HierarchyReader, SoBusReader).map(r => r.shortName -> r.accepted).toMap

  /** The options of `container`'s `@main` method, those of its option groups (such as
    * [[RtlOptions]]) in place, less `hide`; each default read from the parser itself (the
    * method's or the group's default argument), or from `defaults` (and [[groupDefaults]]) where
    * the value is None. */
  def options[B](container: ParserForMethods[B], defaults: Map[String, String] = Map.empty, hide: Set[String] = Set.empty): Seq[Opt] = {
    val stated = groupDefaults ++ defaults
    def show(v: Any): Option[String] = v match {
      case None | _: mainargs.Flag => None
      case Some(x) => show(x)
      case x => Some(valueText(x))
    }
    def walk(sigs: Seq[ArgSig], base: Any): Seq[Opt] = sigs.flatMap { s =>
      s.reader match {
        case c: TokensReader.Class[_] => walk(c.main.argSigs0, c.companion())
        case _ if s.hidden => Seq.empty
        case r =>
          val name = "--" + s.longName(mainargs.Util.kebabCaseNameMapper).getOrElse(s.shortName.fold("")(_.toString))
          val tpe = r match { case n: TokensReader.ShortNamed[_] if !r.isFlag => Some(n.shortName); case _ => None }
          val value = s.default.map(f => f(base))
          val doc = s.doc.getOrElse("")
          // An absent Option whose doc does not say what stands in: none.
          val text = value.flatMap(show).orElse(stated.get(name)).orElse(if (value.contains(None) && !doc.contains("default")) Some("none") else None)
          Seq(Opt(name, s.shortName, tpe, doc, value, text, r))
      }
    }
    walk(container.mains.value.head.argSigs0, container.mains.base()).filterNot(o => hide(o.name)).sortBy(_.name)
  }

  /** The usage `--help` prints: each option with its value type, doc, accepted values and default. */
  def helpText(name: String, opts: Seq[Opt], width: Int = 100): String = {
    def head(o: Opt) = o.short.fold("")(c => s"-$c ") + o.name + o.valueType.fold("")(t => s" <$t>")
    val col = (opts.map(head(_).length).maxOption.getOrElse(0) + 4).min(30)
    def wrap(text: String, indent: Int): Seq[String] = text.split(" ").foldLeft(Vector("")) { (ls, w) =>
      if (ls.last.isEmpty) ls.init :+ w else if (indent + ls.last.length + 1 + w.length > width) ls :+ w else ls.init :+ s"${ls.last} $w"
    }
    val lines = opts.flatMap { o =>
      val default = o.defaultText.map(d => s"(default: $d)").orElse(if (o.required) Some("(required)") else None)
      val doc = Seq(o.doc, o.valueType.flatMap(choices.get).fold("")(c => s"[$c]"), default.getOrElse("")).filter(_.nonEmpty).mkString(" ")
      val h = s"  ${head(o)}"
      val body = wrap(doc, col)
      if (h.length + 2 > col) Seq(h) ++ body.map(" " * col + _)
      else (h.padTo(col, ' ') + body.head) +: body.tail.map(" " * col + _)
    }
    (s"usage: mapm $name [OPTIONS]" +: lines).mkString("\n")
  }

  /** The command-line arguments that give the option group `group` (a mainargs class such as
    * [[RtlOptions]], parsed by `parser`, its nested groups included) its values: `--name value`
    * for each field under the name the parser reads, none for an absent Option or an unset flag.
    * Parsing them gives `group` back (RtlOptionsSpec); a Slurm task reruns a command with them. */
  def toArgs(group: Product, parser: TokensReader.Class[_]): Seq[String] =
    parser.main.argSigs0.zip(group.productIterator.toSeq).flatMap { case (sig, value) =>
      val name = "--" + sig.longName(mainargs.Util.kebabCaseNameMapper).getOrElse(sig.shortName.fold("")(_.toString))
      (sig.reader, value) match {
        case (nested: TokensReader.Class[_], g: Product) => toArgs(g, nested)
        case (_, f: mainargs.Flag) => if (f.value) Seq(name) else Seq.empty
        case (_, None) => Seq.empty
        case (_, Some(v)) => Seq(name, valueText(v))
        case (_, v) => Seq(name, valueText(v))
      }
    }

  /** An option's value as the command line gives it, so that its reader reads it back: a cache
    * geometry as `SIZE/LINE/WAYS`, a number without trailing zeros, anything else as it prints. */
  private def valueText(v: Any): String = v match {
    case c: mapm.pipeline.CacheSpec => c.text
    case d: Double => java.math.BigDecimal.valueOf(d).stripTrailingZeros.toPlainString
    case x => x.toString
  }

  /** [[toArgs]] of the options `render`, `sweep` and `evaluate` share. */
  def toArgs(opts: RtlOptions): Seq[String] = toArgs(opts, rtlOptionsParser)

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
      // The nearest existing folder or file on the way: a file there blocks the folder.
      val blocker = Iterator.iterate(dir)(_.getParent).takeWhile(_ != null).find(java.nio.file.Files.exists(_))
        .filterNot(java.nio.file.Files.isDirectory(_))
      for (b <- blocker) MapmError.fail(s"$opt $value: $b is a file, not a folder${if (b == dir && folders(opt)) " (it names the output folder)" else ""}")
      try java.nio.file.Files.createDirectories(dir)
      catch {
        case e: java.io.IOException =>
          val why = e match {
            case f: java.nio.file.FileAlreadyExistsException => s"${f.getFile} is a file, not a folder"
            case _: java.nio.file.AccessDeniedException      => "permission denied"
            case f: java.nio.file.FileSystemException        => Option(f.getReason).getOrElse("refused")
            case _                                            => String.valueOf(e.getMessage)
          }
          MapmError.fail(s"$opt $value: cannot create the folder $dir: $why")
      }
      MapmError.check(java.nio.file.Files.isWritable(dir), s"$opt $value: the folder $dir is not writable")
    }

  /** A seed must be a non-negative 64-bit number (the harness reads it unsigned). */
  def checkSeed(seed: Long, option: String = "--seed"): Unit =
    MapmError.check(seed >= 0, s"$option must be 0..${Long.MaxValue}, got $seed")

  /** The reader of an option's value of type `T`: `parse` makes it from the option's text (a
    * [[MapmError]] is the message mainargs shows), `shortName` names the type in `--help`, and
    * `accepted` lists the values it takes there. */
  final class ValueReader[T](val shortName: String, val accepted: String, parse: String => T) extends TokensReader.Simple[T] {
    def read(strs: Seq[String]): Either[String, T] =
      try Right(parse(strs.last))
      catch { case e: MapmError => Left(e.getMessage) }
  }

  implicit val FloatFormatReader: ValueReader[FloatFormat] =
    new ValueReader("format", (FloatFormat.presets.map(_._1) :+ "E,M (exponent, fraction bits)").mkString(", "), FloatFormat.parse)
  implicit val ArithReader: ValueReader[mapm.numerics.Arith] =
    new ValueReader("arith", mapm.numerics.Arith.all.mkString(", "), mapm.numerics.Arith.parse)
  implicit val FidelityReader: ValueReader[mapm.params.Fidelity] =
    new ValueReader("fidelity", mapm.params.Fidelity.all.mkString(", "), mapm.params.Fidelity.parse)
  implicit val SlotLayoutReader: ValueReader[SlotLayout] =
    new ValueReader("layout", SlotLayout.all.mkString(", "), SlotLayout.parse)
  implicit val QueryOrderReader: ValueReader[mapm.model.QueryOrder] =
    new ValueReader("order", mapm.model.QueryOrder.all.mkString(", "), mapm.model.QueryOrder.parse)
  implicit val HierarchyReader: ValueReader[mapm.params.Hierarchy] =
    new ValueReader("hierarchy", mapm.params.Hierarchy.all.mkString(", "), mapm.params.Hierarchy.parse)
  implicit val SoBusReader: ValueReader[mapm.params.SoBus] =
    new ValueReader("bus", mapm.params.SoBus.all.mkString(", "), mapm.params.SoBus.parse)
  implicit val CacheSpecReader: ValueReader[mapm.pipeline.CacheSpec] =
    new ValueReader("geometry", "SIZE[/LINE[/WAYS]], e.g. 32K/32/4 or 512K/64/full", mapm.pipeline.CacheSpec.parse)

  /** What each option of the shared groups left out (None) stands for, as `--help` shows it:
    * [[HwOptions]]' sizes are Table 4.2's, read from [[MapmParams.table48]] (a default line too
    * short for a format's record grows to fit it); [[RtlOptions]]' fidelity is full (`evaluate`
    * gives its own). Kept here, not in the groups' companions: an explicit companion hides a case
    * class's default arguments from mainargs. */
  lazy val groupDefaults: Map[String, String] = {
    import mapm.params.Hierarchy.{Scalable, Table42}
    val one = MapmParams.table48(1, 1, 1)
    def geometry(c: CacheParams) = s"${c.sizeBytes / 1024}K/${c.lineBytes}/${if (c.fullyAssociative) "full" else c.ways}"
    val c = one.caches
    val banks16 = Scalable.sopL2Banks(MapmParams.dissertation.counts, c.sopL2)
    Map("--rq-depth" -> one.queues.registerQueueDepth.toString, "--rs-entries" -> s"${one.queues.rsEntries + mapm.params.SoBus.Ring.extraRsPerSoa} per SOA with the ring bus, ${one.queues.rsEntries} with --so-bus serial",
      "--ts-l1" -> s"${geometry(Scalable.tsL1)}; $Table42: ${geometry(Table42.tsL1)}", "--ts-l2" -> geometry(c.tsL2), "--soq" -> s"${geometry(Scalable.soq)}; $Table42: ${geometry(Table42.soq)}",
      "--sop-l1" -> geometry(c.sopL1), "--sop-l2" -> geometry(c.sopL2), "--mem-outstanding" -> one.memory.maxOutstanding.toString,
      "--sop-l2-banks" -> s"one per two SOP L1 banks, $banks16 at 16/16/2; $Table42: 1", "--ts-l2-banks" -> "1",
      "--query-order" -> s"morton; host with --hierarchy $Table42", "--fidelity" -> mapm.params.Fidelity.Full.name,
      "--so-bus" -> s"${mapm.params.SoBus.Ring}; $Table42: ${mapm.params.SoBus.Serial}")
  }

  /** The hardware sizes `emit`, `render`, `sweep` and `evaluate` share (see [[rtlOptionsParser]] for why here). */
  implicit lazy val hwOptionsParser: ParserForClass[HwOptions] = ParserForClass[HwOptions]

  /** The parser of the options `render` and `sweep` share. It lives here, not in the options'
    * companion: mainargs finds a case class's defaults among its companion's members, which are
    * not all known while the companion itself is being compiled (every default was lost). */
  implicit lazy val rtlOptionsParser: ParserForClass[RtlOptions] = ParserForClass[RtlOptions]
}
