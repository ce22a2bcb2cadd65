package mapm.cli

import java.nio.file.Paths

import org.scalatest.funsuite.AnyFunSuite

/** `evaluate`'s choices that need no run: where its page goes. */
class EvaluateCommandSpec extends AnyFunSuite {
  test("evaluate writes its page into the output folder unless --results names one: never docs/results.md unasked") {
    assert(EvaluateCommand.resultsPath(None, "out") == Paths.get("out", "results.md"))
    assert(EvaluateCommand.resultsPath(None, "/tmp/eval") == Paths.get("/tmp/eval/results.md"))
    assert(EvaluateCommand.resultsPath(Some("docs/results.md"), "out") == Paths.get("docs/results.md"))
    // The option's help says where the page goes by default.
    val help = new java.io.ByteArrayOutputStream
    Console.withOut(help)(Console.withErr(help)(EvaluateCommand.run(Seq("--help"))))
    val text = help.toString("UTF-8").replaceAll("\\s+", " ") // the help wraps its lines
    assert(text.contains("default: results.md in --out"), text)
  }
}
