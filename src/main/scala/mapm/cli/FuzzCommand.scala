package mapm.cli

import java.nio.file.Paths

import mainargs.{ParserForMethods, arg, main}
import mapm.MapmError
import mapm.fuzz.LoaderFuzz

/** `mapm fuzz`: the scene readers ([[LoaderFuzz]]) on generated hostile inputs. Prints the count
  * of each kind, how many loaded and how many were rejected with a one-line error, and each input
  * whose outcome was anything else (its files kept under `--out`/fuzz-failures/INDEX). Exit 0 only
  * when there was none. */
object FuzzCommand extends Command {
  val name = "fuzz"
  val summary = "fuzz the OBJ/MTL loader and the scene reader with generated inputs; any outcome but a load or a one-line error fails"

  @main
  def fuzz(
      @arg(doc = "inputs to generate") inputs: Long = 100000,
      @arg(doc = "seed of the generator") seed: Long = 1,
      @arg(doc = "index of the first input (replay one: --from I --inputs 1)") from: Long = 0,
      @arg(doc = "time limit of one input's load, in milliseconds") timeoutMs: Long = 10000,
      @arg(doc = "folder of the shipped files the inputs are made from") scenes: String = "test-scenes/cornell-box",
      @arg(doc = "output folder (failing inputs are kept in fuzz-failures/)") out: String = "out"
  ): Int = {
    Args.checkSeed(seed)
    MapmError.check(inputs >= 1 && inputs <= 100000000L, s"fuzz: --inputs must be 1..100000000, got $inputs")
    MapmError.check(from >= 0, s"fuzz: --from must be at least 0, got $from")
    MapmError.check(timeoutMs >= 100 && timeoutMs <= 600000, s"fuzz: --timeout-ms must be 100..600000, got $timeoutMs")
    val dir = Paths.get(scenes)
    MapmError.check(java.nio.file.Files.isRegularFile(dir.resolve("cornell-box.obj")), s"fuzz: --scenes $dir holds no cornell-box.obj")
    val t0 = System.nanoTime()
    val bar = new mapm.model.Progress("fuzz", inputs)
    val s = LoaderFuzz.run(dir, seed, from, inputs, timeoutMs, Paths.get(out).resolve("fuzz-failures"), () => bar.advance(1))
    bar.finish()
    val secs = (System.nanoTime() - t0) / 1e9
    println(s"fuzz: ${s.inputs} inputs (seed $seed, from $from): ${s.byKind.toSeq.sorted.map { case (k, n) => s"$k $n" }.mkString(", ")}")
    println(f"fuzz: ${s.loaded}%d loaded, ${s.rejected}%d rejected with a one-line error, ${s.failures.size}%d failures in $secs%.1f s")
    for (f <- s.failures.take(20))
      println(s"FAIL input ${f.index} (${f.kind}): ${f.what}; replay: tools/mapm fuzz --seed $seed --from ${f.index} --inputs 1")
    if (s.failures.nonEmpty) MapmError.fail(s"fuzz: ${s.failures.size} of ${s.inputs} inputs failed (files in ${Paths.get(out).resolve("fuzz-failures")})")
    0
  }

  lazy val parser: ParserForMethods[_] = ParserForMethods(this)

  def run(args: Seq[String]): Int = Args.run(this, args)
}
