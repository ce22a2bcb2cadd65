package mapm.fuzz

import java.nio.file.{Files, Path, StandardCopyOption}
import java.util.concurrent.{Executors, TimeUnit, TimeoutException}

import scala.util.Random

import mapm.MapmError
import mapm.model.{ObjLoader, SceneConfig}
import mapm.numerics.Vec3

/** Fuzzes the readers of user files: the OBJ/MTL loader ([[ObjLoader]]) and the scene-file reader
  * ([[SceneConfig]], which also loads the OBJ it names). Input `i` of seed `s` is generated from
  * those two numbers alone ([[Mutator]]) from the shipped Cornell-box OBJ, MTL and scene files:
  *
  *  - `obj`: 1 to 4 text edits of the OBJ; `mtl`: of the MTL (both read by the OBJ loader);
  *  - `scene-json`: 1 to 3 structural edits of a shipped scene (values replaced by extreme numbers,
  *    wrong types, nested junk; keys removed or added); `scene-text`: text edits of one;
  *  - `bytes`: random bytes as the OBJ, the MTL or the scene; `truncated`: a prefix of a file;
  *  - `deep`: a scene of thousands of nested arrays or objects.
  *
  * The only allowed outcomes are a successful load or a [[MapmError]] whose message is one line.
  * Anything else (another exception, a load that runs past the time limit, running out of memory)
  * is a [[LoaderFuzz.Failure]], with the input's files kept for replay. */
final class LoaderFuzz(sceneDir: Path, work: Path, timeoutMs: Long) {
  import LoaderFuzz._

  private def read(name: String): String = new String(Files.readAllBytes(sceneDir.resolve(name)), "UTF-8")
  private val objText = read("cornell-box.obj")
  private val mtlText = read("cornell-box.mtl")
  private val scenes: IndexedSeq[String] = {
    val names = Seq("scene.json", "scene-small.json", "scene-area.json", "scene-full.json").filter(n => Files.isRegularFile(sceneDir.resolve(n)))
    MapmError.check(names.nonEmpty, s"fuzz: no scene files in $sceneDir")
    names.map(read).toIndexedSeq
  }
  private val jsonTokens = IndexedSeq("{", "}", "[", "]", ",", ":", "\"", "\"obj\"", "\"photons\"", "null", "true", "{\"auto\": 1e9}")
  private def newExecutor() = Executors.newSingleThreadExecutor { (r: Runnable) =>
    // The stack tools/mapm gives its main thread (-Xss16m), so recursion limits are the CLI's.
    val t = new Thread(null, r, "fuzz-target", 16L << 20); t.setDaemon(true); t
  }
  private var executor = newExecutor()

  /** The files of input `index` of `seed`, and which reader takes them. */
  def generate(seed: Long, index: Long): Input = {
    val r = new Random(seed * 0x9e3779b97f4a7c15L ^ index * 0xbf58476d1ce4e5b9L)
    def edits(text: String, n: Int, tokens: IndexedSeq[String]) = (1 to n).foldLeft(text)((t, _) => Mutator.mutateText(r, t, tokens))
    val scene = scenes(r.nextInt(scenes.size))
    val base = Input("", Mutator.bytes(objText), Mutator.bytes(mtlText), Mutator.bytes(scene), readsScene = true)
    r.nextInt(16) match {
      case 0 | 1 | 2 | 3 => base.copy(kind = "obj", obj = Mutator.bytes(edits(objText, 1 + r.nextInt(4), Mutator.ObjTokens)), readsScene = false)
      case 4 | 5 => base.copy(kind = "mtl", mtl = Mutator.bytes(edits(mtlText, 1 + r.nextInt(4), Mutator.ObjTokens)), readsScene = false)
      case 6 | 7 | 8 | 9 =>
        val json = (1 to 1 + r.nextInt(3)).foldLeft(ujson.read(scene))((v, _) => Mutator.mutateJson(r, v))
        base.copy(kind = "scene-json", scene = Mutator.bytes(ujson.write(json)))
      case 10 | 11 => base.copy(kind = "scene-text", scene = Mutator.bytes(edits(scene, 1 + r.nextInt(3), jsonTokens)))
      case 12 => r.nextInt(3) match {
        case 0 => base.copy(kind = "bytes", obj = Mutator.randomBytes(r, 4000), readsScene = false)
        case 1 => base.copy(kind = "bytes", mtl = Mutator.randomBytes(r, 2000), readsScene = false)
        case _ => base.copy(kind = "bytes", scene = Mutator.randomBytes(r, 2000))
      }
      case 13 => r.nextInt(3) match {
        case 0 => base.copy(kind = "truncated", obj = base.obj.take(r.nextInt(base.obj.length)), readsScene = false)
        case 1 => base.copy(kind = "truncated", mtl = base.mtl.take(r.nextInt(base.mtl.length)), readsScene = false)
        case _ => base.copy(kind = "truncated", scene = base.scene.take(r.nextInt(base.scene.length)))
      }
      case _ => base.copy(kind = "deep", scene = Mutator.bytes(Mutator.deepJson(r, 1 + r.nextInt(if (r.nextBoolean()) 100 else 200000))))
    }
  }

  /** Writes `in` into the work folder and runs its reader: Right(true) when it loads, Right(false)
    * when it is rejected with a one-line [[MapmError]], Left(what went wrong) otherwise. */
  def check(in: Input): Either[String, Boolean] = {
    Files.write(work.resolve("cornell-box.obj"), in.obj)
    Files.write(work.resolve("cornell-box.mtl"), in.mtl)
    Files.write(work.resolve("scene.json"), in.scene)
    outcome {
      if (in.readsScene) SceneConfig.load(work.resolve("scene.json")) else ObjLoader.load(work.resolve("cornell-box.obj"), Vec3(0.5, 0.5, 0.5))
    }
  }

  /** Runs `load` on the worker thread: Right(true) when it returns, Right(false) for a one-line
    * [[MapmError]], Left(what) for anything else: another exception or error, a MapmError message
    * that is empty or more than one line, no outcome within the time limit. */
  def outcome(load: => Any): Either[String, Boolean] = {
    val task = executor.submit[Either[String, Boolean]] { () =>
      try { load; Right(true) }
      catch {
        case e: MapmError =>
          val m = e.getMessage
          if (m == null || m.isEmpty || m.exists(c => c == '\n' || c == '\r')) Left(s"a MapmError message that is not one line: ${String.valueOf(m).take(200)}")
          else Right(false)
        case e: OutOfMemoryError => Left(s"out of memory (${e.getMessage})")
        case _: StackOverflowError => Left("stack overflow")
        case e: Throwable => Left(s"${e.getClass.getName}: ${String.valueOf(e.getMessage).linesIterator.nextOption().getOrElse("")}")
      }
    }
    try task.get(timeoutMs, TimeUnit.MILLISECONDS)
    catch {
      case _: TimeoutException =>
        // Abandon the stuck worker (a daemon) so the next input gets a fresh one.
        task.cancel(true); executor.shutdownNow(); executor = newExecutor()
        Left(s"no outcome within $timeoutMs ms (a hang)")
    }
  }

  /** Keeps the files of a failing input in `dir`. */
  def keep(in: Input, dir: Path): Unit = {
    Files.createDirectories(dir)
    for (f <- Seq("cornell-box.obj", "cornell-box.mtl", "scene.json"))
      Files.copy(work.resolve(f), dir.resolve(f), StandardCopyOption.REPLACE_EXISTING)
  }

  def close(): Unit = executor.shutdownNow()
}

object LoaderFuzz {
  /** One generated input: the three files (the scene names `cornell-box.obj`, which names
    * `cornell-box.mtl`) and whether the scene reader (else the OBJ loader) takes them. */
  final case class Input(kind: String, obj: Array[Byte], mtl: Array[Byte], scene: Array[Byte], readsScene: Boolean)

  /** An input whose outcome was not allowed. */
  final case class Failure(index: Long, kind: String, what: String)

  /** Counts of one run. */
  final case class Summary(inputs: Long, loaded: Long, rejected: Long, byKind: Map[String, Long], failures: Seq[Failure])

  /** Runs inputs `from` until `from + count` of `seed`; `keepDir` receives each failing input's
    * files (in a folder named by its index); `progress` is told of each input done. */
  def run(sceneDir: Path, seed: Long, from: Long, count: Long, timeoutMs: Long, keepDir: Path,
          progress: () => Unit = () => ()): Summary = {
    val work = Files.createTempDirectory("mapm-fuzz")
    val fuzz = new LoaderFuzz(sceneDir, work, timeoutMs)
    var loaded, rejected = 0L
    val kinds = scala.collection.mutable.Map.empty[String, Long].withDefaultValue(0L)
    val failures = Seq.newBuilder[Failure]
    try {
      for (i <- from until from + count) {
        val in = fuzz.generate(seed, i)
        kinds(in.kind) += 1
        fuzz.check(in) match {
          case Right(true) => loaded += 1
          case Right(false) => rejected += 1
          case Left(what) =>
            failures += Failure(i, in.kind, what)
            fuzz.keep(in, keepDir.resolve(i.toString))
        }
        progress()
      }
    } finally {
      fuzz.close()
      Files.list(work).forEach(f => Files.deleteIfExists(f))
      Files.deleteIfExists(work)
    }
    Summary(count, loaded, rejected, kinds.toMap, failures.result())
  }
}
