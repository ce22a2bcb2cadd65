// mapm: Chisel generator and software model of the Multi-Accelerator for Photon Mapping.
// Every version below was checked to resolve and work together on the project's machines.

ThisBuild / scalaVersion := "2.13.15"
ThisBuild / version      := "0.1.0"
ThisBuild / organization := "mapm"

val chiselVersion = "6.7.0"

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
    Compile / run / javaOptions ++= Seq("-Xss16m", "-Xmx8g", s"-Dmapm.root=${baseDirectory.value}"),
    Compile / mainClass := Some("mapm.cli.Main"),
    Test / fork := true,
    Test / javaOptions ++= Seq("-Xss16m", "-Xmx8g", s"-Dmapm.root=${baseDirectory.value}"),
    Test / parallelExecution := false,
    Test / testOptions += Tests.Argument(TestFrameworks.ScalaTest, "-oD")
  )
