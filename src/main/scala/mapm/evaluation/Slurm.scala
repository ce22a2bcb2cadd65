package mapm.evaluation

import java.nio.file.{Files, Path}

import scala.jdk.CollectionConverters._
import scala.sys.process.{Process, ProcessLogger}

import mapm.MapmError

/** Runs independent jobs as a Slurm job array (docs/cluster.md): one array task per job, each
  * running mapm with the submitting command's own arguments and `--task N`, then one
  * collect step, after every task has ended (`afterany`, so that a failed task is reported, not
  * waited for), that merges the tasks' result files. The submitting command waits for the collect
  * step (`sbatch --wait`) and ends with its exit status. The tasks run in the submitting folder,
  * on the submitting JVM's classpath ([[launcher]]): no task compiles, all run the same code. */
object Slurm {
  /** The checks of the options every command that runs jobs takes (`--jobs`, `--slurm`, `--partition`, `--task`, `--collect`). */
  def checkOptions(command: String, jobs: Int, slurm: Boolean, partition: Option[String], task: Option[Int], collect: Boolean): Unit = {
    MapmError.check(jobs >= 1 && jobs <= 256, s"$command: --jobs must be 1..256, got $jobs")
    MapmError.check(partition.isEmpty || slurm, s"$command: --partition applies to --slurm runs only")
    MapmError.check(!(slurm && (task.isDefined || collect)), s"$command: --slurm submits the tasks; --task and --collect are the tasks' own")
  }

  /** `args` quoted for a POSIX shell. */
  def quote(args: Seq[String]): String =
    args.map(a => if (a.nonEmpty && a.forall(c => c.isLetterOrDigit || "-_./=,:+@%".contains(c))) a else "'" + a.replace("'", "'\\''") + "'").mkString(" ")

  /** `args` without the flags that only the submitting command takes (each with its value where it has one). */
  def strip(args: Seq[String], flags: Set[String], valued: Set[String]): Seq[String] = {
    val out = Seq.newBuilder[String]
    var i = 0
    while (i < args.length) {
      val a = args(i)
      val key = a.takeWhile(_ != '=')
      if (valued(key)) i += (if (a.contains('=')) 1 else 2)
      else if (flags(a)) i += 1
      else { out += a; i += 1 }
    }
    out.result()
  }

  /** This JVM again, on its own classpath and with its own heap, stack and property flags: every
    * task runs exactly the code of the submitting command, and none compiles anything. */
  def launcher: Seq[String] = {
    val jvm = java.nio.file.Paths.get(sys.props("java.home"), "bin", "java").toString
    val flags = java.lang.management.ManagementFactory.getRuntimeMXBean.getInputArguments.asScala.toSeq.filter(a => a.startsWith("-X") || a.startsWith("-D"))
    (jvm +: flags) ++ Seq("-cp", sys.props("java.class.path"), "mapm.cli.Main")
  }

  private def sbatch: String =
    mapm.SetupScript.which("sbatch").map(_.toString).getOrElse(MapmError.fail("--slurm: sbatch not found on PATH (Slurm's client commands are needed; tools/slurm-local.sh starts a one-node cluster)"))

  /** Submits `tasks` array tasks running `mapm command taskArgs --task N`, then the collect step
    * `mapm command taskArgs --collect`, logs in `logDir`; waits for the collect step and returns
    * its exit status. */
  def run(command: String, taskArgs: Seq[String], tasks: Int, partition: Option[String], logDir: Path, log: String => Unit): Int = {
    MapmError.check(tasks >= 1, "--slurm: nothing to run")
    val exe = sbatch
    Files.createDirectories(logDir)
    val part = partition.toSeq.flatMap(p => Seq("--partition", p))
    def wrap(extra: String) = s"cd ${quote(Seq(new java.io.File(".").getCanonicalPath))} && exec ${quote(launcher ++ (command +: taskArgs))} $extra"
    def submit(opts: Seq[String], script: String): String = {
      val out = new StringBuilder
      val cmd = Seq(exe, "--parsable") ++ part ++ opts ++ Seq("--wrap", script)
      val rc = Process(cmd).!(ProcessLogger(l => out.append(l).append('\n'), l => out.append(l).append('\n')))
      MapmError.check(rc == 0, s"--slurm: sbatch failed (exit $rc): ${out.toString.trim.linesIterator.toSeq.lastOption.getOrElse("")}")
      out.toString.trim.linesIterator.toSeq.last.takeWhile(_ != ';')
    }
    val array = submit(Seq("--job-name", s"mapm-$command", s"--array=0-${tasks - 1}", "--cpus-per-task=1",
      "--output", logDir.resolve("task-%a.log").toAbsolutePath.toString), wrap("--task $SLURM_ARRAY_TASK_ID"))
    log(s"submitted Slurm array job $array: $tasks tasks (logs in $logDir/task-N.log)")
    val collectLog = logDir.resolve("collect.log")
    log(s"waiting for the collect step (after every task of $array; log $collectLog) ...")
    val rc = Process(Seq(exe, "--wait", "--job-name", s"mapm-$command-collect", s"--dependency=afterany:$array",
      "--output", collectLog.toAbsolutePath.toString) ++ part ++ Seq("--wrap", wrap("--collect")))
      .!(ProcessLogger(_ => (), l => log(s"sbatch: $l")))
    if (Files.isRegularFile(collectLog)) print(new String(Files.readAllBytes(collectLog), java.nio.charset.StandardCharsets.UTF_8))
    rc
  }
}
