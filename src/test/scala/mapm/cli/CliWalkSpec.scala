package mapm.cli

import java.io.ByteArrayOutputStream
import java.nio.file.{Files, Paths}
import java.util.concurrent.{Executors, TimeUnit, TimeoutException}

import mapm.MapmError
import org.scalatest.funsuite.AnyFunSuite

/** Walks every option of every command (read from the command's own `--help`) with bad values of
  * its type: not a number, negative, past the type's range, NaN, an unknown format, arithmetic or
  * layout, a path under a regular file (which can be neither read nor created). Every run must end
  * quickly in a one-line [[MapmError]] that names the option (so `mapm` prints it and exits 1):
  * never another exception (which `mapm` reports as an internal error), never a silent success.
  * The other options hold small valid values, so a bad value that slips through is noticed (the
  * run succeeds or times out) rather than starting a long job. */
class CliWalkSpec extends AnyFunSuite {
  private val work = Paths.get("target/cli-walk")
  private val small = "test-scenes/cornell-box/scene-small.json"
  private lazy val tsaIn = {
    Files.createDirectories(work)
    Files.write(work.resolve("tsa.csv"), "p,h,s\n0x3c00,0x3800,0x3e00\n".getBytes("UTF-8"))
  }
  private lazy val soaIn = Some(mapm.testutil.SharedDir.file("vectors/fp16_g3_public.csv")).filter(Files.isRegularFile(_))

  /** Valid options that keep each command's run small: what the walk keeps unless it varies it. */
  private def base(cmd: String): Seq[(String, String)] = cmd match {
    case "render" => Seq("scene" -> small, "tsm" -> "1", "som" -> "1", "soa" -> "1", "out" -> s"$work/out")
    case "sweep" => Seq("scene" -> small, "configs" -> "1/1/1", "out" -> s"$work/out")
    case "bench-sim" => Seq("scene" -> small, "tsm" -> "1", "som" -> "1", "soa" -> "1", "out" -> s"$work/out")
    case "stress" => Seq("configs" -> "1/1/1", "seeds" -> "1", "out" -> s"$work/out")
    case "model" | "bench-model" => Seq("scene" -> small, "out" -> s"$work/out", "threads" -> "1")
    case "kdtree" => Seq("photons" -> "test-scenes/table-3-1/photons.csv")
    case "bench-search" => Seq("photons" -> "500", "queries" -> "50", "repeat" -> "1", "warmup" -> "0", "threads" -> "1")
    case "emit" => Seq("tsm" -> "1", "som" -> "1", "soa" -> "1", "format" -> "5,4", "out" -> s"$work/emit")
    case "evaluate" => Seq("quick" -> "", "out" -> s"$work/out", "results" -> s"$work/results.md")
    case "emit-tsa" => Seq("format" -> "4,3", "out" -> s"$work/emit-tsa")
    case "emit-soa" => Seq("format" -> "4,4", "out" -> s"$work/emit-soa")
    case "tsa-vectors" => Seq("in" -> tsaIn.toString, "format" -> "fp16")
    case "soa-vectors" => Seq("in" -> soaIn.map(_.toString).getOrElse("/nonexistent.csv"), "format" -> "fp16")
    case "soa-bench" => Seq("ops" -> "100", "format" -> "fp16")
    case "cost" => Seq("unit" -> "tsa", "format" -> "5,4", "scene" -> small, "ops" -> "200", "out" -> s"$work/cost")
    case "fuzz" => Seq("inputs" -> "5", "out" -> s"$work/out")
    case "format" => Seq("values" -> "1.5", "format" -> "fp16")
    case "precision" => Seq("formats" -> "5,4", "arith" -> "online", "no-frame-time" -> "", "scene" -> small, "out" -> s"$work/out")
    case _ => Seq.empty
  }

  /** Each option of `cmd` and its value type, from the help text (`--name <type>`). */
  private def options(cmd: Command): Seq[(String, String)] = {
    val out = new ByteArrayOutputStream()
    Console.withOut(out)(cmd.run(Seq("--help")))
    """(?m)^\s+(?:-\w )?--([a-z][a-z0-9-]*) <(\w+)>""".r.findAllMatchIn(out.toString("UTF-8")).map(m => m.group(1) -> m.group(2)).toSeq
  }

  private val unwritable = "/proc/version/x" // under a regular file: cannot exist, cannot be made

  private def badValues(tpe: String): Seq[String] = tpe match {
    case "int" => Seq("abc", "-7", "99999999999")
    case "long" => Seq("abc", "-7", "99999999999999999999")
    case "double" => Seq("abc", "-7", "NaN")
    case "format" => Seq("fp33", "e99m99")
    case "arith" => Seq("quantum")
    case "layout" => Seq("tight")
    case "fidelity" => Seq("approximate")
    case "geometry" => Seq("abc", "0", "16K/x/2", "16K/32/0", "16K/32/2/1", "15K")
    case _ => Seq(unwritable)
  }

  private val pool = Executors.newSingleThreadExecutor { (r: Runnable) => val t = new Thread(null, r, "cli-walk", 16L << 20); t.setDaemon(true); t }

  /** Runs `cmd` with `args`: Right(the error message) for a MapmError, Left(what else happened). */
  private def attempt(cmd: Command, args: Seq[String]): Either[String, String] = {
    val task = pool.submit[Either[String, String]] { () =>
      val sink = new ByteArrayOutputStream()
      try Console.withOut(sink)(Console.withErr(sink)(cmd.run(args))) match {
        case 0 => Left("succeeded")
        case rc => Left(s"returned $rc without an error message")
      } catch {
        case e: MapmError => Right(e.getMessage)
        case e: Throwable => Left(s"internal error: ${e.getClass.getSimpleName}: ${e.getMessage}")
      }
    }
    try task.get(120, TimeUnit.SECONDS)
    catch { case _: TimeoutException => task.cancel(true); Left("no error within 120 s (the value was not checked before the work)") }
  }

  for (cmd <- Main.commands) test(s"${cmd.name}: every option rejects bad values with a one-line error naming it") {
    if (cmd.name == "soa-vectors") assume(soaIn.isDefined, "../shared/vectors is absent")
    val opts = options(cmd)
    assert(opts.nonEmpty, s"${cmd.name} --help lists no options")
    val problems = for {
      (name, tpe) <- opts
      v <- badValues(tpe)
      args = (base(cmd.name).filter(_._1 != name) :+ (name -> v)).flatMap { case (k, "") => Seq(s"--$k"); case (k, x) => Seq(s"--$k", x) }
      problem <- attempt(cmd, args) match {
        case Left(what) => Some(s"--$name $v: $what")
        case Right(msg) if msg.contains('\n') => Some(s"--$name $v: a message of more than one line: $msg")
        case Right(msg) if msg.contains("internal error") => Some(s"--$name $v: $msg")
        case Right(msg) if !msg.contains(name) && !msg.contains(v) => Some(s"--$name $v: the message names neither the option nor the value: $msg")
        case _ => None
      }
    } yield problem
    assert(problems.isEmpty, problems.mkString("\n"))
  }

  test("no command: tools/mapm prints the usage on stderr and exits 2; --help prints it and exits 0") {
    assert(sys.props.get("mapm.bare-run").isEmpty, "the test JVM is not a bare sbt run")
    val out = new java.io.ByteArrayOutputStream
    val err = new java.io.ByteArrayOutputStream
    val rc = Console.withOut(out)(Console.withErr(err)(Main.dispatch(Seq.empty)))
    assert(rc == 2 && out.size == 0)
    assert(err.toString("UTF-8").startsWith("usage: mapm COMMAND") && Main.commands.forall(c => err.toString("UTF-8").contains(c.name)))
    val help = new java.io.ByteArrayOutputStream
    assert(Console.withOut(help)(Main.dispatch(Seq("--help"))) == 0 && help.toString("UTF-8").startsWith("usage: mapm COMMAND"))
  }

  test("a mistyped option is named alone, with the nearest one the command takes; a bad value gives its reason alone") {
    def err(c: Command, args: String*): String = intercept[mapm.MapmError](c.run(args)).getMessage
    val typo = err(ModelCommand, "--scnee", "test-scenes/cornell-box/scene-small.json", "--out", "x1")
    assert(typo == "model: unknown option --scnee (did you mean --scene?) (mapm model --help lists the options)", typo)
    assert(err(RenderCommand, "--fomat", "fp16").contains("unknown option --fomat (did you mean --format?)"))
    assert(err(RenderCommand, "--tsm", "2", "--latncy-max", "9").contains("unknown option --latncy-max (did you mean --latency-max?)"))
    val far = err(ModelCommand, "--tsm", "2")
    assert(far.startsWith("model: unknown option --tsm (mapm model --help"), far) // nothing model takes is near it
    val value = err(RenderCommand, "--format", "fp128")
    assert(value.startsWith("render: Invalid argument --format <format> failed to parse \"fp128\"") && value.contains("unknown float format 'fp128'"), value)
    assert(!value.contains("Expected Signature"), value)
    assert(Args.nearest("--sed", Set("--seed", "--scene")) == Some("--seed") && Args.nearest("--qu", Set("--quick", "--out")) == Some("--quick"))
  }

  /** Each option's entry in `cmd --help` (its line and the indented lines after it, spaces
    * collapsed), by option name. */
  private def helpEntries(cmd: Command): Seq[(String, String)] = {
    val o = new ByteArrayOutputStream
    assert(Console.withOut(o)(cmd.run(Seq("--help"))) == 0)
    o.toString("UTF-8").split("\n(?=  -)").toSeq.tail.map(_.replaceAll("\\s+", " ").trim)
      .map(e => """(--[a-z][a-z0-9-]*)""".r.findFirstIn(e).get -> e)
  }

  test("--help lists what the parser takes, each default read from the parser, and the shown default parses back to it") {
    for (cmd <- Main.commands) {
      val listed = helpEntries(cmd)
      assert(listed.map(_._1) == cmd.options.map(_.name), s"${cmd.name}: the help lists every option the parser takes, once")
      val problems = listed.flatMap { case (name, said) =>
        val o = cmd.options.find(_.name == name).get
        val roundTrip = (o.defaultValue, o.defaultText, o.reader) match {
          case (Some(v), Some(t), r: mainargs.TokensReader.Simple[_]) if !v.isInstanceOf[Option[_]] =>
            r.read(Seq(t)) match {
              case Right(back) if back == v => None
              case other => Some(s"${cmd.name} $name: shows default '$t', which parses to $other, not $v")
            }
          case _ => None
        }
        // Every value option says its default (or that it is required, or what stands in for it).
        val stated = if (o.valueType.isEmpty || said.contains("(required)") || said.contains("default")) None
          else Some(s"${cmd.name} $name: no default shown: $said")
        val twice = if (o.defaultText.isDefined && o.doc.contains("default")) Some(s"${cmd.name} $name: a default in the doc and another shown: $said") else None
        roundTrip.toSeq ++ stated ++ twice
      }
      assert(problems.isEmpty, problems.mkString("\n"))
    }
  }

  test("--help says what matters at a glance: render's sizes default to 16/16/2, model takes fp64, evaluate takes no --scene") {
    val render = helpEntries(RenderCommand).toMap
    for ((o, d) <- Seq("--tsm" -> "16", "--som" -> "16", "--soa" -> "2", "--latency" -> "100", "--bandwidth" -> "14", "--clock-ghz" -> "1.5",
        "--out" -> "out", "--scene" -> RenderCommand.defaultScene, "--fidelity" -> "full", "--ts-l1" -> "16K/64/2; table4.2: 16K/32/2", "--rs-entries" -> "10 per SOA with the ring bus, 8 with --so-bus serial", "--so-bus" -> "ring; table4.2: serial"))
      assert(render(o).endsWith(s"(default: $d)"), render(o))
    assert(helpEntries(ModelCommand).toMap.apply("--format").contains("fp64"))
    val evaluate = helpEntries(EvaluateCommand).toMap
    assert(!evaluate.contains("--scene") && evaluate("--fidelity").endsWith("(default: timing)"))
    val e = intercept[MapmError](EvaluateCommand.run(Seq("--quick", "--scene", "x.json")))
    assert(e.getMessage.startsWith("evaluate: unknown option --scene"), e.getMessage)
  }

  test("an output folder named by a file is refused before any work, naming the file in the way") {
    val file = Files.createTempFile("not-a-folder", ".txt")
    def err(args: String*): String = intercept[MapmError](ModelCommand.run(args)).getMessage
    assert(err("--out", file.toString) == s"--out $file: $file is a file, not a folder (it names the output folder)")
    assert(err("--out", file.resolve("sub").toString) == s"--out ${file.resolve("sub")}: $file is a file, not a folder")
  }
}
