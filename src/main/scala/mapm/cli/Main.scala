package mapm.cli

import mapm.MapmError

/** One sub-command of the `mapm` tool. Each lives in its own file and parses its own flags
  * (with mainargs); [[Main]] only dispatches on the first word. */
trait Command {
  /** The word that selects it, e.g. `model`. */
  def name: String
  /** One line for `mapm --help`. */
  def summary: String
  /** The mainargs parser of its `@main` method. */
  def parser: mainargs.ParserForMethods[_]
  /** What an option whose default value is None stands for in this command, as `--help` shows it. */
  def optionDefaults: Map[String, String] = Map.empty
  /** Options of a shared group ([[RtlOptions]]) that this command does not take. */
  def hiddenOptions: Set[String] = Set.empty
  /** Its options as `--help` lists them ([[Args.options]]). */
  def options: Seq[Args.Opt] = Args.options(parser, optionDefaults, hiddenOptions)
  /** Runs with the remaining arguments; returns the process exit code. */
  def run(args: Seq[String]): Int
}

/** Entry point of `tools/mapm` and `tools/sbt "run ..."`.
  *
  * Every [[MapmError]] becomes one line `mapm: <message>` on stderr and exit code 1 (so does a
  * file that cannot be read or written, an IOException); any other
  * exception is reported the same way as an internal error (its stack trace only when
  * MAPM_DEBUG=1), so a user never sees a stack trace for bad input.
  */
object Main {
  val commands: Seq[Command] = Seq(
    RenderCommand,
    SweepCommand,
    EvaluateCommand,
    ModelCommand,
    FormatCommand,
    KdtreeCommand,
    BenchSearchCommand,
    BenchModelCommand,
    BenchSimCommand,
    EmitCommand,
    EmitTsaCommand,
    TsaVectorsCommand,
    EmitSoaCommand,
    SoaVectorsCommand,
    SoaBenchCommand,
    CostCommand,
    PrecisionCommand,
    StressCommand,
    FuzzCommand,
    LintCommand
  )

  def usage: String = {
    val w = commands.map(_.name.length).maxOption.getOrElse(0)
    val lines = commands.map(c => s"  ${c.name.padTo(w, ' ')}  ${c.summary}")
    ("usage: mapm COMMAND [OPTIONS]   (mapm COMMAND --help for its options)" +: "commands:" +: lines)
      .mkString("\n")
  }

  /** Runs the command `args` names. With no command at all, a bare `tools/sbt run` (whose JVM has
    * `-Dmapm.bare-run=emit`, build.sbt) emits the default configuration's Verilog into out/mapm, as
    * chisel-template projects do; `tools/mapm` prints the usage on stderr and exits 2. */
  def dispatch(args: Seq[String]): Int = args match {
    case Seq() if sys.props.get("mapm.bare-run").contains("emit") =>
      println("mapm: no command given: emitting the default configuration, as `mapm emit` (`tools/sbt \"run --help\"` lists the commands)")
      EmitCommand.run(Seq.empty)
    case Seq() => Console.err.println(usage); 2
    case Seq("--help") | Seq("-h") | Seq("help") => println(usage); 0
    case cmd +: rest =>
      commands.find(_.name == cmd) match {
        case Some(c) => c.run(rest)
        case None    => MapmError.fail(s"unknown command '$cmd'\n$usage")
      }
  }

  def main(args: Array[String]): Unit = {
    val code =
      try dispatch(args.toSeq)
      catch {
        case e: MapmError =>
          System.err.println(s"mapm: ${e.getMessage}"); 1
        case e @ (_: java.io.IOException | _: java.io.UncheckedIOException) =>
          System.err.println(s"mapm: cannot read or write a file: ${e.getClass.getSimpleName}: ${String.valueOf(e.getMessage).linesIterator.nextOption().getOrElse("")}"); 1
        case e: OutOfMemoryError =>
          System.err.println("mapm: out of memory (raise -Xmx through MAPM_JAVA_OPTS, or render a smaller scene)"); 1
        case e: Throwable =>
          if (sys.env.get("MAPM_DEBUG").contains("1")) e.printStackTrace()
          System.err.println(s"mapm: internal error: ${e.getClass.getSimpleName}: ${e.getMessage} (MAPM_DEBUG=1 shows the trace)")
          2
      }
    System.out.flush()
    sys.exit(code)
  }
}
