// mapm: Chisel generator and software model of the Multi-Accelerator for Photon Mapping.
// Every version below was checked to resolve and work together on the project's machines.

ThisBuild / scalaVersion := "2.13.15"
ThisBuild / version      := "0.1.0"
ThisBuild / organization := "mapm"

val chiselVersion = "6.7.0"

/** Forked test JVMs that run at once: MAPM_TEST_JVMS, else one per core up to 2 (more JVMs than
  * cores only add heap and contention; each Verilator build already uses every core). */
val testJvms: Int = sys.env.get("MAPM_TEST_JVMS").flatMap(s => scala.util.Try(s.toInt).toOption).filter(_ >= 1)
  .getOrElse(math.max(1, math.min(2, java.lang.Runtime.getRuntime.availableProcessors)))

// The spec classes run in forked JVMs at once, spread by their measured seconds so that both cores
// of a small machine stay busy (docs/testing.md). Each class weighs its seconds in
// project/test-times.tsv (the cold-run profile; `tools/test-profile --write` refreshes it from a
// run's reports), or 10 s when it is not there yet. The classes go, heaviest first, each to the
// JVM with the least weight so far (longest processing time first), and each JVM runs its classes
// heaviest first, so the short ones fill the end. Classes named on one `together` line of the file
// share files and run in the same JVM, one after the other.

/** Reads project/test-times.tsv: (seconds by class, sets of classes that run together). Lines are
  * `class<TAB>seconds[<TAB>what it waits on]` or `together<TAB>class<TAB>class...`; `#` starts a
  * comment; a missing file is an empty profile. */
def readTestTimes(file: File): (Map[String, Double], Seq[Set[String]]) = {
  val rows = if (!file.exists) Seq.empty[Seq[String]]
    else IO.readLines(file).map(_.trim).filter(l => l.nonEmpty && !l.startsWith("#")).map(_.split("\t").toSeq)
  val together = rows.collect { case Seq("together", names @ _*) => names.toSet }
  val seconds = rows.collect { case Seq(name, secs, _*) if name != "together" && secs.matches("[0-9.]+") => name -> secs.toDouble }
  (seconds.toMap, together)
}

/** The spec classes of `tests` in at most `jvms` groups, as described above; no empty group. */
def splitTests(tests: Seq[TestDefinition], times: (Map[String, Double], Seq[Set[String]]), jvms: Int): Seq[Seq[TestDefinition]] = {
  val (seconds, together) = times
  def weight(t: TestDefinition): Double = seconds.getOrElse(t.name, 10.0)
  // Units that stay in one JVM: a `together` set, or a class alone.
  val bound = together.map(s => tests.filter(t => s(t.name))).filter(_.nonEmpty)
  val boundNames = bound.flatten.map(_.name).toSet
  val units = bound ++ tests.filterNot(t => boundNames(t.name)).map(Seq(_))
  val loads = Array.fill(jvms)(0.0)
  val groups = Array.fill(jvms)(Vector.empty[TestDefinition])
  for (u <- units.sortBy(u => (-u.map(weight).sum, u.head.name))) {
    val i = loads.indices.minBy(k => (loads(k), k))
    loads(i) += u.map(weight).sum
    groups(i) ++= u
  }
  groups.toSeq.filter(_.nonEmpty).map(_.sortBy(t => (-weight(t), t.name)))
}

/** Extracts firtool (Chisel's FIRRTL compiler, shipped in the llvm-firtool jar) into
  * ~/.cache/llvm-firtool before the test JVMs start: each extracts it on first use, and two doing so
  * at once raced on a cold machine (one ran the binary before the other had made it executable:
  * "Permission denied"). Runs one small emit in a JVM of its own when no extracted binary is there yet. */
lazy val firtoolReady = taskKey[Unit]("extracts firtool once, before the test JVMs that would race to extract it")

def onPath(tool: String): Boolean =
  sys.env.getOrElse("PATH", "").split(java.io.File.pathSeparator).exists(d => new java.io.File(d, tool).canExecute)

lazy val root = (project in file("."))
  .settings(
    name := "mapm",
    libraryDependencies ++= Seq(
      "org.chipsalliance" %% "chisel"     % chiselVersion,
      "edu.berkeley.cs"   %% "chiseltest" % "6.0.0" % Test,
      "org.scalatest"     %% "scalatest"  % "3.2.19" % Test,
      "com.lihaoyi"       %% "mainargs"   % "0.7.6",
      "com.lihaoyi"       %% "ujson"      % "3.1.0", // the version chisel itself depends on
      "de.javagl"          % "obj"        % "0.4.0",
      "me.tongfei"         % "progressbar" % "0.10.1", // newest 0.10.x, checked to resolve from Maven Central
      "org.knowm.xchart"   % "xchart"      % "3.8.8"   // checked to resolve from Maven Central
    ),
    addCompilerPlugin("org.chipsalliance" % "chisel-plugin" % chiselVersion cross CrossVersion.full),
    scalacOptions ++= Seq(
      "-language:reflectiveCalls",
      "-deprecation",
      "-feature",
      "-Xcheckinit",
      "-Ymacro-annotations"
    ),
    Compile / run / fork := true,
    Compile / run / connectInput := true,
    // A bare `sbt run` emits the default configuration's Verilog (mapm.cli.Main.dispatch).
    Compile / run / javaOptions ++= Seq("-Xss16m", "-Xmx8g", s"-Dmapm.root=${baseDirectory.value}", "-Dmapm.bare-run=emit"),
    Compile / mainClass := Some("mapm.cli.Main"),
    Test / fork := true,
    Test / javaOptions ++= Seq("-Xss16m", "-Xmx6g", "-XX:+UseParallelGC", s"-Dmapm.root=${baseDirectory.value}"),
    // chiseltest's Verilator builds go through ccache too (its make reads OBJCACHE), paths taken
    // relative to the checkout so that a fresh clone hits the cache of an earlier one.
    // The tests' Verilator builds compile their C++ at -O1: 41 % less compile time than -Os, and
    // the short test runs simulate as fast (src/main/scala/mapm/sim/Verilator.scala, docs/testing.md).
    Test / envVars += "MAPM_CXX_OPT" -> "-O1",
    // Whole-MAPM harnesses at -O0: the tests' frames simulate in about a second at -O1, and -O0
    // compiles each in about 45 % less CPU (docs/testing.md).
    Test / envVars += "MAPM_HARNESS_CXX_OPT" -> "-O0",
    // chiseltest's builds: Verilator 5.006 puts its OPT_FAST (-Os) after chiseltest's -O1, so they
    // compiled at -Os; make takes variables from MAKEFLAGS as from its command line, so -O1 holds.
    Test / envVars += "MAKEFLAGS" -> "OPT_FAST=-O1 OPT_SLOW=-O0 OPT_GLOBAL=-O1",
    Test / envVars ++= (if (onPath("ccache")) Map("OBJCACHE" -> "ccache", "CCACHE_BASEDIR" -> baseDirectory.value.getAbsolutePath)
                        else Map.empty[String, String]),
    // The groups below run at once (parallelExecution lets sbt start them together); the spec
    // classes within one JVM run one after the other (testForkedParallel).
    Test / parallelExecution := true,
    Test / testForkedParallel := false,
    firtoolReady := {
      val cp = (Test / fullClasspath).value.files
      // firtool-resolver fetches and extracts llvm-firtool at run time, into ~/.cache/llvm-firtool/<version>/bin.
      val versions = Option((file(sys.props("user.home")) / ".cache" / "llvm-firtool").listFiles).toSeq.flatten
      if (!versions.exists(v => (v / "bin" / "firtool").canExecute)) {
        val log = streams.value.log
        log.info("extracting firtool once, before the test JVMs ...")
        val javaBin = file(sys.props("java.home")) / "bin" / "java"
        val out = target.value / "firtool-warmup"
        val rc = scala.sys.process.Process(Seq(javaBin.getAbsolutePath, "-cp", cp.map(_.getAbsolutePath).mkString(java.io.File.pathSeparator),
          s"-Dmapm.root=${baseDirectory.value.getAbsolutePath}", "mapm.cli.Main", "emit-tsa", "--format", "5,4", "--out", out.getAbsolutePath),
          baseDirectory.value).!(log)
        if (rc != 0) sys.error(s"firtool could not be extracted (emit-tsa exited with $rc)")
      }
    },
    // The spec classes in `testJvms` forked JVMs at once, spread by their measured seconds (above).
    Test / testGrouping := {
      firtoolReady.value
      val opts = ForkOptions().withRunJVMOptions((Test / javaOptions).value.toVector)
        .withEnvVars((Test / envVars).value).withWorkingDirectory(baseDirectory.value)
      val times = readTestTimes(baseDirectory.value / "project" / "test-times.tsv")
      val groups = splitTests((Test / definedTests).value, times, testJvms)
      groups.zipWithIndex.map { case (tests, i) => Tests.Group(s"jvm-${i + 1}", tests, Tests.SubProcess(opts)) }
    },
    Test / testOptions += Tests.Argument(TestFrameworks.ScalaTest, "-oD")
  )

// sbt's defaults run one forked test group at a time (Tags.limit(ForkedTestGroup, 1)); these
// replace them, keeping the rest of the defaults.
Global / concurrentRestrictions := Seq(
  Tags.limitAll(math.max(testJvms, java.lang.Runtime.getRuntime.availableProcessors)),
  Tags.limit(Tags.ForkedTestGroup, testJvms),
  Tags.exclusiveGroup(Tags.Clean))
