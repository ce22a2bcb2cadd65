package mapm.cost

import java.nio.charset.StandardCharsets
import java.nio.file.{Files, Path}
import mapm.MapmError
import scala.sys.process._

/** Static timing and power of a synthesized netlist by OpenSTA (Debian's `opensta`, 2019).
  *
  * One OpenSTA session per netlist: the clock is created on port `clock` with every other input
  * arriving and every output required at the clock edge (register-to-register, input-to-register
  * and register-to-output paths, as a unit in a pipeline). For each requested clock it reports
  * the worst setup slack, the critical path and the power; fmax is found by bisection on the
  * period (to 0.5 ps) with the same netlist.
  *
  * Power uses the switching activity handed in per pin (transitions per clock cycle and the
  * fraction of time high): OpenSTA turns it into transitions per second at each clock. This
  * OpenSTA has no read_vcd/read_saif, its `set_power_activity -pins` is broken, and activities set
  * before the first `report_power` are dropped; so the script calls `report_power` once, then sets
  * every pin with `sta::set_power_pin_activity` (ports with `sta::set_power_input_port_activity`).
  * A global activity (`set_power_activity -global`) would override every pin's, so it is set only
  * when no pin activity is given.
  *
  * Clock gates: OpenSTA clocks every register behind a clock gate in every cycle (it takes the
  * clock's activity for a clock pin, whatever activity the pin is given). So with `gated` levels
  * (the cells whose power follows one gate's clock, and the fraction of cycles it runs) the power
  * is found twice more: per instance with every gate running, then with every gate stopped
  * (`set_case_analysis 0` on the gates' latch outputs, `stopPins`), in total at each clock and per
  * instance. The reported power is the stopped total plus, for each level, its duty times what
  * its cells draw beyond the stopped figure (dynamic power is linear in each clock's rate);
  * [[AtClock.ungatedDynamicMw]] is the same sum with every gate open in every cycle. The stops are lifted
  * before fmax is searched. The switching of the gated clock nets is left out (see
  * [[GatedLevel]]), in the stopped total too, where those nets are constant.
  */
object Sta {
  /** Timing and power at one clock. Power in mW, times in ns. */
  final case class AtClock(clockGHz: Double, periodNs: Double, worstSlackNs: Double, startPoint: String,
                           endPoint: String, arrivalNs: Double, internalMw: Double, switchingMw: Double,
                           leakageMw: Double, ungatedDynamicMw: Option[Double] = None) {
    def slackMet: Boolean = worstSlackNs >= 0
    def dynamicMw: Double = internalMw + switchingMw
  }
  final case class Report(clocks: Seq[AtClock], fmaxGHz: Double, seconds: Double)

  /** The transition (ns) given to the clock pins behind a clock gate, standing in for the clock
    * tree a layout flow would build: one gate output drives them all in the synthesized netlist,
    * and its slew would put each flip-flop's internal power thousands of times too high. */
  val GatedClockTransitionNs = 0.1

  /** Activity of one pin or input port: transitions per clock cycle and duty (fraction of time 1). */
  final case class Activity(activity: Double, duty: Double)

  /** The cells whose dynamic power beyond the stopped-clock figure scales with `duty`, the
    * fraction of cycles their clock runs (the flip-flops behind one clock gate and the logic of its
    * gated clock; or a gate's latch, duty 1). The switching power of `clockDrivers` (those that
    * drive a gated clock net) is left out, as the root clock net's always is (a port drives it):
    * the clock distribution's switching is a clock tree's, which no flow here builds. */
  final case class GatedLevel(cells: Seq[String], duty: Double, clockDrivers: Set[String] = Set.empty)

  /** Runs OpenSTA on `netlists` (module `top`) at each clock in `clocksGHz`. `pinActivity` maps
    * instance pins (`inst/PIN`) and `portActivity` input port bits (`name[i]` or `name`) to their
    * activity; `defaultActivity` applies to input ports not listed and, when no activity is listed
    * at all, to every pin. Writes the script and log into `workDir`. */
  def run(netlistFiles: Seq[Path], top: String, libFile: Path, clocksGHz: Seq[Double], workDir: Path,
          pinActivity: Iterable[(String, Activity)], portActivity: Iterable[(String, Activity)],
          defaultActivity: Activity = Activity(0.1, 0.5), clockPort: String = "clock",
          gated: Seq[GatedLevel] = Seq.empty, stopPins: Seq[String] = Seq.empty): Report = {
    MapmError.check(clocksGHz.nonEmpty && clocksGHz.forall(c => c > 0 && c < 100), s"cost: clocks must be in (0, 100) GHz, got ${clocksGHz.mkString(",")}")
    val dir = workDir.toAbsolutePath
    val netlists = netlistFiles.map(_.toAbsolutePath)
    val lib = libFile.toAbsolutePath
    Files.createDirectories(dir)
    val tcl = dir.resolve("sta.tcl")
    val act = dir.resolve("activity.tcl")
    val w = Files.newBufferedWriter(act, StandardCharsets.UTF_8)
    try {
      for ((pin, a) <- pinActivity) w.write(f"sta::set_power_pin_activity [get_pins {$pin}] ${a.activity}%.6g ${a.duty}%.6g\n")
      for ((port, a) <- portActivity) w.write(f"sta::set_power_input_port_activity [get_ports {$port}] ${a.activity}%.6g ${a.duty}%.6g\n")
    } finally w.close()
    val gatesTcl = dir.resolve("gates.tcl")
    val gw = Files.newBufferedWriter(gatesTcl, StandardCharsets.UTF_8)
    try {
      gw.write("set mapm_gate_cells {}\n")
      for (c <- gated.flatMap(_.cells).distinct) gw.write(s"lappend mapm_gate_cells {$c}\n")
      gw.write("set mapm_stop_pins {}\n")
      for (p <- stopPins) gw.write(s"lappend mapm_stop_pins {$p}\n")
    } finally gw.close()
    val periods = clocksGHz.map(1.0 / _)
    val script =
      s"""|read_liberty {$lib}
          |${netlists.map(n => s"read_verilog {$n}").mkString("\n")}
          |link_design {$top}
          |set clk_port [get_ports -quiet {$clockPort}]
          |proc mapm_clock {period} {
          |  global clk_port
          |  if {[llength $$clk_port] > 0} { create_clock -name clk -period $$period $$clk_port } else { create_clock -name clk -period $$period }
          |  set ins [all_inputs]
          |  if {[llength $$clk_port] > 0} { set ins [delete_from_list $$ins $$clk_port] }
          |  if {[llength $$ins] > 0} { set_input_delay 0 -clock clk $$ins }
          |  if {[llength [all_outputs]] > 0} { set_output_delay 0 -clock clk [all_outputs] }
          |}
          |proc mapm_slack {} { return [sta::worst_slack -max] }
          |# Gated clocks: a clock gate's output drives every register behind it (tens of thousands in a
          |# SOM) with no clock tree, which layout would build; its loads get a clock tree's transition.
          |set mapm_gated {}
          |set mapm_nets [dict create]
          |foreach n [get_nets -quiet -of_objects [all_registers -clock_pins]] { dict set mapm_nets [get_full_name $$n] $$n }
          |dict for {name n} $$mapm_nets {
          |  set pins [get_pins -quiet -of_objects $$n]
          |  set driven 0
          |  foreach p $$pins { if {[get_property $$p direction] == "output"} { set driven 1 } }
          |  if {$$driven} { foreach p $$pins { if {[get_property $$p direction] == "input"} { lappend mapm_gated $$p } } }
          |}
          |if {[llength $$mapm_gated] > 0} { set_assigned_transition ${GatedClockTransitionNs} $$mapm_gated }
          |puts "MAPM_GATED [llength $$mapm_gated]"
          |mapm_clock ${periods.head}
          |${if (pinActivity.isEmpty && portActivity.isEmpty) s"set_power_activity -global -activity ${defaultActivity.activity} -duty ${defaultActivity.duty}" else ""}
          |set_power_activity -input -activity ${defaultActivity.activity} -duty ${defaultActivity.duty}
          |report_power > /dev/null
          |source {$act}
          |foreach period {${periods.mkString(" ")}} {
          |  mapm_clock $$period
          |  puts "MAPM_CLOCK $$period [mapm_slack]"
          |  report_checks -path_delay max -sort_by_slack -digits 4 -format full
          |  report_power -digits 6
          |  puts "MAPM_END"
          |}
          |${if (gated.isEmpty) "" else s"""source {$gatesTcl}
          |mapm_clock ${periods.head}
          |puts "MAPM_CELLS_RUNNING"
          |report_power -instances [get_cells $$mapm_gate_cells] -digits 6
          |puts "MAPM_CELLS_END"
          |foreach p $$mapm_stop_pins { set_case_analysis 0 [get_pins $$p] }
          |foreach period {${periods.mkString(" ")}} {
          |  mapm_clock $$period
          |  puts "MAPM_STOPPED $$period [mapm_slack]"
          |  report_power -digits 6
          |  puts "MAPM_END"
          |}
          |mapm_clock ${periods.head}
          |puts "MAPM_CELLS_STOPPED"
          |report_power -instances [get_cells $$mapm_gate_cells] -digits 6
          |puts "MAPM_CELLS_END"
          |foreach p $$mapm_stop_pins { unset_case_analysis [get_pins $$p] }"""}
          |# fmax by bisection on the period (lo fails, hi meets), bracketed around period - slack
          |mapm_clock ${periods.head}
          |set d [expr ${periods.head} - [mapm_slack]]
          |set hi [expr $$d * 1.01 + 0.001]
          |mapm_clock $$hi
          |while {[mapm_slack] < 0} { set hi [expr $$hi * 1.1]; mapm_clock $$hi }
          |set lo [expr $$d * 0.99]
          |mapm_clock $$lo
          |while {[mapm_slack] >= 0 && $$lo > 1e-6} { set lo [expr $$lo * 0.9]; mapm_clock $$lo }
          |while {$$hi - $$lo > 0.0005} {
          |  set mid [expr ($$lo + $$hi) / 2.0]
          |  mapm_clock $$mid
          |  if {[mapm_slack] >= 0} { set hi $$mid } else { set lo $$mid }
          |}
          |puts "MAPM_FMAX_PERIOD $$hi"
          |exit
          |""".stripMargin
    Files.write(tcl, script.getBytes(StandardCharsets.UTF_8))
    val t0 = System.nanoTime()
    val text = runSta(tcl, dir.resolve("sta.log"), s"on $top", "MAPM_FMAX_PERIOD", 0)
    val clocks = parseClocks(text)
    Report(if (gated.isEmpty) clocks else gatedPower(text, clocks, gated, periods.head),
      1.0 / """MAPM_FMAX_PERIOD ([0-9.eE+-]+)""".r.findFirstMatchIn(text).get.group(1).toDouble,
      (System.nanoTime() - t0) / 1e9)
  }

  /** The clocks' power with each gated level at its duty (see the class comment): the stopped
    * totals plus each level's duty times its cells' running-minus-stopped power, measured at
    * `period0` and scaled to each clock. */
  private[cost] def gatedPower(text: String, running: Seq[AtClock], gated: Seq[GatedLevel], period0: Double): Seq[AtClock] = {
    def cells(marker: String): Map[String, (Double, Double)] = {
      val body = text.split(marker).lift(1).getOrElse(MapmError.fail(s"OpenSTA printed no $marker section")).split("MAPM_CELLS_END")(0)
      (("""(?m)^\s*""" + num + """\s+""" + num + """\s+""" + num + """\s+""" + num + """\s+(\S+)\s*$""").r.findAllMatchIn(body)
        .map(m => m.group(5) -> (m.group(1).toDouble * 1e3, m.group(2).toDouble * 1e3)).toMap)
    }
    val (on, off) = (cells("MAPM_CELLS_RUNNING"), cells("MAPM_CELLS_STOPPED"))
    // OpenSTA keeps a stopped gate's clock net switching (the clock still reaches it): that, too,
    // is the clock distribution's, taken out of the stopped total.
    val driversSw = gated.flatMap(_.clockDrivers).distinct.map(c => off.get(c).map(_._2).getOrElse(0.0)).sum
    def delta(c: String): (Double, Double) = {
      val (a, b) = (on.getOrElse(c, MapmError.fail(s"OpenSTA reported no power for $c")), off.getOrElse(c, (0.0, 0.0)))
      (a._1 - b._1, a._2 - b._2)
    }
    // Each level's extra internal and switching power at period0, times its duty.
    val levels = gated.map { l =>
      val d = l.cells.map(c => if (l.clockDrivers(c)) (delta(c)._1, 0.0) else delta(c))
      (l.duty, d.map(_._1).sum, d.map(_._2).sum)
    }
    val (extraInt, extraSw) = (levels.map(l => l._1 * l._2).sum, levels.map(l => l._1 * l._3).sum)
    val always = levels.map(l => l._2 + l._3).sum // every gate open
    val stopped = parseSections(text, "MAPM_STOPPED ")
    running.zip(stopped).map { case (r, s) =>
      val scale = period0 / r.periodNs
      val stoppedSw = s.switchingMw - driversSw * scale
      r.copy(internalMw = s.internalMw + extraInt * scale, switchingMw = stoppedSw + extraSw * scale,
        ungatedDynamicMw = Some(s.internalMw + stoppedSw + always * scale))
    }
  }

  /** The whole design's timing, every path between its modules included: fmax, the worst paths
    * and the trial periods of the search that found it. */
  final case class Whole(fmaxGHz: Double, instances: Long, worst: Seq[WholePath], trials: Seq[(Double, Double)], seconds: Double)
  /** One endpoint's worst path: its start and end points, its slack at the period found (ns), and
    * the module instances it runs through in order (`.` for the top's own cells). */
  final case class WholePath(startPoint: String, endPoint: String, slackNs: Double, through: Seq[String])

  /** Times the hierarchical netlist `netlistFiles` of `top` as one design (timing only, no
    * power), linked whole so that the paths from one module into another are timed with the
    * rest. For designs too large for the per-module flow's bisection: one OpenSTA session loads
    * the design once, and [[PeriodSearch]] asks it for the worst slack at a few trial periods
    * (a clock gate's enable latch takes half a period, so the period is not the first trial's
    * period minus its slack). The clocks are ideal. Each of the `paths` worst endpoints is
    * reported at the period found. The configuration inputs (`io_cfg...`), which hold their
    * value for a whole frame, start no path. A positive `memoryLimitBytes` caps OpenSTA's
    * address space (`prlimit`); past it the run fails. Each trial is told to `progress`. The
    * session's commands are kept in `sta-whole.tcl` and its output in `sta-whole.log`. */
  def timeWhole(netlistFiles: Seq[Path], top: String, libFile: Path, workDir: Path, paths: Int = 5,
                clockPort: String = "clock", memoryLimitBytes: Long = 0, progress: String => Unit = _ => ()): Whole = {
    val dir = workDir.toAbsolutePath
    Files.createDirectories(dir)
    val (tcl, log) = (dir.resolve("sta-whole.tcl"), dir.resolve("sta-whole.log"))
    val setup =
      s"""|read_liberty {${libFile.toAbsolutePath}}
          |${netlistFiles.map(n => s"read_verilog {${n.toAbsolutePath}}").mkString("\n")}
          |link_design {$top}
          |puts "MAPM_INSTANCES [sta::network_leaf_instance_count]"
          |set clk_port [get_ports -quiet {$clockPort}]
          |set ins [delete_from_list [all_inputs] $$clk_port]
          |proc mapm_clock {period} {
          |  global clk_port ins
          |  create_clock -name clk -period $$period $$clk_port
          |  if {[llength $$ins] > 0} { set_input_delay 0 -clock clk $$ins }
          |  if {[llength [all_outputs]] > 0} { set_output_delay 0 -clock clk [all_outputs] }
          |}
          |mapm_clock 10
          |# Configuration inputs hold one value for a whole frame: no path starts at them.
          |set cfg [get_ports -quiet {io_cfg*}]
          |if {[llength $$cfg] > 0} { set_false_path -from $$cfg }
          |# Every clock pin gets a clock tree's transition: a gate's output drives its registers across
          |# the hierarchy with no tree (see GatedClockTransitionNs); the clock is ideal, so its latency is 0.
          |set_assigned_transition ${GatedClockTransitionNs} [all_registers -clock_pins]
          |proc mapm_slack_at {period} { mapm_clock $$period; return [sta::worst_slack -max] }
          |proc mapm_paths {} {
          |  foreach path [find_timing_paths -path_delay max -group_count $paths -endpoint_count 1 -sort_by_slack] {
          |    set through {}
          |    foreach pt [get_property $$path points] {
          |      set inst [file dirname [file dirname [get_full_name [get_property $$pt pin]]]]
          |      if {[llength $$through] == 0 || [lindex $$through end] != $$inst} { lappend through $$inst }
          |    }
          |    puts "MAPM_PATH [get_full_name [get_property $$path startpoint]] [get_full_name [get_property $$path endpoint]] [get_property $$path slack] [join $$through ,]"
          |  }
          |}
          |puts "MAPM_READY"
          |""".stripMargin
    Files.write(tcl, setup.getBytes(StandardCharsets.UTF_8))
    val t0 = System.nanoTime()
    val limit = if (memoryLimitBytes > 0) Seq("prlimit", s"--as=$memoryLimitBytes") else Seq.empty
    val proc = new java.lang.ProcessBuilder((limit ++ Seq(CostTools.get.sta.toString, "-no_init", "-no_splash")): _*)
      .directory(dir.toFile).redirectErrorStream(true).start()
    val out = new StringBuilder
    val in = new java.io.BufferedReader(new java.io.InputStreamReader(proc.getInputStream, StandardCharsets.UTF_8))
    val cmd = new java.io.PrintWriter(new java.io.OutputStreamWriter(proc.getOutputStream, StandardCharsets.UTF_8), true)
    def fail(why: String): Nothing = {
      Files.write(log, out.toString.getBytes(StandardCharsets.UTF_8))
      proc.destroy()
      MapmError.fail(s"OpenSTA failed timing $top whole: $why (log $log)")
    }
    /** Sends `command` (which prints a line starting with `marker` when it succeeds) and reads
      * OpenSTA's output up to that line, which it returns. OpenSTA echoes each command after its
      * prompt; a Tcl error in the command is caught and printed as one line. */
    def ask(command: String, marker: String): String = {
      cmd.println(s"""if {[catch {$command} mapm_err]} { puts "MAPM_FAIL [string map {\\n { }} $$mapm_err]" }""")
      var line = in.readLine()
      while (line != null && !line.startsWith(marker)) {
        out.append(line).append('\n')
        if (line.startsWith("MAPM_FAIL ")) fail(line.stripPrefix("MAPM_FAIL ").trim)
        if (line.startsWith("Error")) fail(line.trim)
        line = in.readLine()
      }
      if (line == null) fail(s"it ended (exit ${proc.waitFor()}) before printing $marker")
      out.append(line).append('\n')
      line
    }
    try {
      ask(s"source {$tcl}", "MAPM_READY")
      def slackAt(period: Double): Double = {
        val m = (s"MAPM_SLACK $num").r.findFirstMatchIn(ask(s"""puts "MAPM_SLACK [mapm_slack_at $period]"""", "MAPM_SLACK"))
        val slack = m.fold(fail(s"no slack at $period ns"))(_.group(1).toDouble)
        progress(f"whole at $period%.4f ns: worst slack $slack%.4f ns")
        slack
      }
      val found = try PeriodSearch.minPeriod(slackAt, 10.0, toleranceNs = 0.002) catch { case e: MapmError => fail(e.getMessage) }
      for ((p, sl) <- found.trials) out.append(s"MAPM_TRIAL $p $sl\n")
      ask(s"mapm_clock ${found.periodNs}; mapm_paths; puts MAPM_PATHS_END", "MAPM_PATHS_END")
      cmd.println("exit"); proc.waitFor()
      val text = out.toString
      Files.write(log, text.getBytes(StandardCharsets.UTF_8))
      val worst = ("""MAPM_PATH (\S+) (\S+) """ + num + """ (\S*)""").r.findAllMatchIn(text)
        .map(m => WholePath(m.group(1), m.group(2), m.group(3).toDouble, m.group(4).split(',').toSeq.filter(_.nonEmpty))).toSeq
      Whole(1.0 / found.periodNs, """MAPM_INSTANCES ([0-9]+)""".r.findFirstMatchIn(text).map(_.group(1).toLong).getOrElse(0L), worst,
        found.trials, (System.nanoTime() - t0) / 1e9)
    } finally { cmd.close(); proc.destroy() }
  }

  private val num = """(-?[0-9.]+(?:[eE][+-]?[0-9]+)?)"""

  /** Runs OpenSTA on `tcl` in its folder, keeps its output in `log` and returns it; fails with one
    * line when OpenSTA exits non-zero, prints an error or never prints `done` (its result line).
    * A `memoryLimitBytes` above zero caps its address space (`prlimit`), so that a design too large
    * for the machine makes OpenSTA fail alone (an allocation error) rather than bring the kernel's
    * out-of-memory killer onto the other processes. */
  private def runSta(tcl: Path, log: Path, what: String, done: String, memoryLimitBytes: Long): String = {
    val out = new StringBuilder
    val limit = if (memoryLimitBytes > 0) Seq("prlimit", s"--as=$memoryLimitBytes") else Seq.empty
    val rc = Process(limit ++ Seq(CostTools.get.sta.toString, "-no_init", "-no_splash", "-exit", tcl.toString), tcl.getParent.toFile)
      .!(ProcessLogger(l => out.append(l).append('\n'), l => out.append(l).append('\n')))
    Files.write(log, out.toString.getBytes(StandardCharsets.UTF_8))
    val text = out.toString
    val errors = text.linesIterator.filter(l => l.startsWith("Error") || l.contains("error:")).toSeq
    if (rc != 0 || errors.nonEmpty || !text.contains(done))
      MapmError.fail(s"OpenSTA failed $what: ${errors.headOption.getOrElse(s"exit $rc")} (log $log)")
    text
  }

  private[cost] def parseClocks(text: String): Seq[AtClock] = parseSections(text, "MAPM_CLOCK ")

  private def parseSections(text: String, marker: String): Seq[AtClock] =
    text.split(marker).drop(1).toSeq.map { sec =>
      val body = sec.split("MAPM_END")(0)
      val head = body.linesIterator.next().trim.split("\\s+")
      val period = head(0).toDouble
      val slack = head(1).toDouble
      val start = """Startpoint: (\S+)""".r.findFirstMatchIn(body).map(_.group(1)).getOrElse("-")
      val end = """Endpoint: (\S+)""".r.findFirstMatchIn(body).map(_.group(1)).getOrElse("-")
      val arrival = (num + """\s+data arrival time""").r.findFirstMatchIn(body).map(_.group(1).toDouble).getOrElse(0.0)
      val total = ("""(?m)^Total\s+""" + num + """\s+""" + num + """\s+""" + num + """\s+""" + num).r.findFirstMatchIn(body)
        .getOrElse(MapmError.fail("OpenSTA printed no power total"))
      AtClock(1.0 / period, period, slack, start, end, arrival,
        total.group(1).toDouble * 1e3, total.group(2).toDouble * 1e3, total.group(3).toDouble * 1e3)
    }
}
