package mapm.costflow

import java.nio.charset.StandardCharsets
import java.nio.file.{Files, Path}
import mapm.cost._
import mapm.sim.{Emit, MapmRtl}
import mapm.params.{Fidelity, MapmParams}
import mapm.top.Mapm
import mapm.util.{Boundary, CostBlock}
import mapm.MapmError

/** The cost of a whole MAPM configuration, two ways side by side (docs/cost.md):
  *
  *  (a) the dissertation's method (Table 4.9): the SOA's and the TSA's unit figures times their
  *      counts, at a common clock;
  *  (b) the synthesized logic of every module: the whole design synthesized once, each distinct
  *      module generically once; the top, its blocks, the blocks' parts (TSM, SOM, Query fetch,
  *      L2 caches, Data bus, arbiters) and every cache stay modules, and everything else is
  *      flattened into them, so that ABC maps, buffers and sizes each of them whole. Each kept module's cells count
  *      once per instance. The caches' and Register-queue banks' SRAM arrays (`SyncReadMem`s) are
  *      black boxes: their bits are reported per block and their area estimated from a bit-cell
  *      model ([[ConfigCost.SramModel]]), their energy from the accesses of a rendered frame
  *      ([[SramEnergy]]) when one is given.
  *
  * Timing and power of (b): each kept module without kept modules inside is analysed whole by
  * OpenSTA; the others (the top, the blocks, TSMs and SOM lanes around their L1 caches) for their
  * own logic, with the kept modules inside as empty shells; these give each part's fmax and power.
  * Then the whole netlist is linked and timed at once ([[Sta.timeWhole]]), which times every path
  * from one part into another; fmax is the lower of the whole design's and the parts' (they agree
  * unless a part's own analysis is the stricter), and `crossPartTimed` says whether the whole run
  * fitted the machine. Power uses one global activity, the mean net activity the SOA showed in
  * its gate-level simulation, except for the SOA itself (kept whole): its power and energy per
  * operation are its own gate-level run's, clock gates at their measured duty.
  */
object ConfigCost {
  /** SRAM bit-cell area model for the black-boxed arrays: a 6T cell of Intel's 180 nm logic
    * process (5.59 um^2, IEDM 1998) at 70 % array efficiency (decoders, sense amplifiers). */
  object SramModel {
    val cellUm2 = 5.59
    val efficiency = 0.70
    def areaUm2(bits: Long): Double = bits * cellUm2 / efficiency
    val source = "6T bit cell of 5.59 um^2 (Intel 180 nm logic process, IEDM 1998) at 70 % array efficiency"
  }

  /** The design synthesized for method (b): its top, module hierarchy and SRAM arrays, each
    * module's own cells, every instance path under the top, each module's instance count, the
    * synthesis result and its seconds. */
  private final case class Synthesized(top: String, hier: Hierarchy, mems: Seq[String], own: Map[String, ModuleCells.Own],
                                       paths: Seq[Seq[String]], inst: Map[String, Long], result: Synthesis.Result, seconds: Double,
                                       tags: Map[String, CostBlock], comb: Map[String, Seq[CombPaths.Path]], registered: Set[String]) {
    /** The cost block of the instance at the end of `chain` (the tag its module or the nearest
      * module above it got at elaboration); an untagged module under the top is an error. */
    def block(chain: Seq[String]): String = CostBlock.of(chain, tags).fold(mapm.MapmError.fail, _.name)
  }

  /** Method (a) at clock `clk`: unit figures times counts; dynamic power scales with the clock at a
    * fixed activity per cycle. */
  private def methodA(nSoa: Int, nTsa: Int, soa: UnitCost, tsa: UnitCost)(clk: Double): ujson.Obj =
    ujson.Obj("clockGHz" -> clk, "slackMet" -> (clk <= math.min(soa.fmaxGHz, tsa.fmaxGHz) + 1e-9),
      "areaMm2" -> (nSoa * soa.areaUm2 + nTsa * tsa.areaUm2) / 1e6,
      "dynamicPowerMw" -> (nSoa * soa.dynamicMwAt(clk) + nTsa * tsa.dynamicMwAt(clk)),
      "leakagePowerMw" -> (nSoa * soa.clocks.head.leakageMw + nTsa * tsa.clocks.head.leakageMw))

  /** The modules method (b) keeps whole (everything else is flattened into them): the MAPM's
    * blocks (`core`'s children), their parts (TSM, SOM, Query fetch, L2 caches, Data bus,
    * arbiters) and every cache; when `top` wraps the MAPM (the coprocessor), also the wrapper's
    * own modules and their parts (stream reader, frame accumulator, its combining network and
    * FIFOs, ...), and the `units` found in the design (the SOA, whose power comes from its own
    * gate-level run). Memory arrays are left out: they are black boxes. */
  private[costflow] def keptModules(hier: Hierarchy, top: String, core: String, units: Seq[String] = Nil): Seq[String] = {
    def below(ms: Seq[String]): Seq[String] =
      ms.flatMap(m => hier.children.getOrElse(m, Nil)).distinct.filterNot(hier.memories.contains)
    MapmError.check(top == core || below(Seq(top)).contains(core), s"cost: $top does not instantiate the MAPM $core")
    val blocks = below(Seq(core))
    val wrapper = if (top == core) Nil else { val own = below(Seq(top)); own ++ below(own.filterNot(_ == core)) }
    val caches = hier.children.keys.filter(_.startsWith("ROCache")).toSeq.sorted // kept too: their logic counts as caches
    val kept = (wrapper ++ blocks ++ below(blocks) ++ caches).distinct
    kept ++ units.filter(hier.children.contains).filterNot(kept.contains)
  }

  /** Emits `p` for synthesis and synthesizes it once: the blocks, their parts and every cache
    * kept as modules, the SRAM arrays black boxes. */
  private def synthesize(flow: CostFlow, p: MapmParams, units: Seq[String], dir: Path, log: String => Unit): Synthesized = {
    val top = mapm.sim.MapmRtl.topName(p)
    mapm.sim.MapmRtl.checkEmittable(p)
    log(s"emitting $top for synthesis ...")
    val ((sv, tags), registered) = Boundary.collect(CostBlock.collect(
      Emit.toFile(if (p.sim.coproc) new mapm.soc.MapmCoproc(p) else new Mapm(p), dir.resolve("rtl"), s"$top.sv", forSynthesis = true)))
    val hier = Hierarchy.parse(new String(Files.readAllBytes(sv), StandardCharsets.UTF_8))
    val mems = hier.memories.keys.toSeq.sorted
    val kept = keptModules(hier, top, s"Mapm_${p.name}", units)
    log(s"synthesizing $top: ${kept.size} parts and blocks kept whole, ${mems.size} SRAM arrays as black boxes ...")
    val delayPs = math.round(1000.0 / flow.clocksGHz.max).toInt
    val (syn, synSecs) = SynthesisCache.run(Seq(sv), top, flow.libPath, delayPs, Seq("buffer"), dir.resolve("synth"),
      flatten = false, blackbox = mems, keep = kept)
    val json = YosysJson.read(syn.head.json)
    val own = ModuleCells.of(json, syn.head.json.toString, flow.library)
    // Every instance path under the top; a module's instance count is the number of paths ending in it.
    val paths = {
      val out = scala.collection.mutable.ArrayBuffer.empty[Seq[String]]
      def walk(chain: Seq[String]): Unit = { out += chain; own.get(chain.last).foreach(_.children.foreach(c => walk(chain :+ c))) }
      walk(Seq(top)); out.toSeq
    }
    val inst = paths.groupBy(_.last).map { case (m, ps) => m -> ps.size.toLong }
    Synthesized(top, hier, mems, own, paths, inst, syn.head, synSecs, tags, combPaths(json, syn.head.json.toString, own, inst.keySet, flow), registered)
  }

  /** The combinational input-to-output paths of every module in `modules`, each found in its own
    * cells and through its kept submodules' paths (bottom up; SRAM arrays end a path). */
  private def combPaths(json: ujson.Value, source: String, own: Map[String, ModuleCells.Own], modules: Set[String],
                        flow: CostFlow): Map[String, Seq[CombPaths.Path]] = {
    val memo = scala.collection.mutable.Map.empty[String, Seq[CombPaths.Path]]
    def of(m: String): Seq[CombPaths.Path] = memo.getOrElse(m, {
      val kids = own(m).children.distinct
      val sub = kids.filter(k => own.get(k).exists(o => o.cells > 0 || o.children.nonEmpty)).map(k => k -> of(k)).toMap
      val r = CombPaths.of(Netlist.fromJson(json, source, Some(m), kids.toSet), flow.library, sub)
      memo(m) = r
      r
    })
    modules.filter(own.contains).map(m => m -> of(m)).toMap
  }

  /** The boundary check: every part that states a registered boundary ([[Boundary]]) has no
    * combinational input-to-output path (configuration inputs aside); a line per violation. */
  def boundaryViolations(j: ujson.Value): Seq[String] =
    j("methodB")("boundaries")("modules").arr.toSeq.filter(m => m("registered").bool && m("paths").num > 0).map { m =>
      s"${m("module").str} must have no combinational input-to-output path but has ${m("paths").num.toLong}, e.g. ${m("examples").arr.head.str}"
    }

  /** OpenSTA's timing and power of every module of `d` at the flow's clocks and `meanActivity`:
    * modules with kept modules inside (the top, the blocks) as shells, the rest whole. */
  private def analyse(flow: CostFlow, d: Synthesized, meanActivity: Double, dir: Path, log: String => Unit): Seq[(Analysis, Sta.Report)] = {
    val shells = d.own.keySet.filter(m => d.inst.contains(m) && d.own(m).children.exists(c => !d.mems.contains(c)))
    val whole = d.own.keySet.filter(m => d.inst.contains(m) && !shells(m) && !d.mems.contains(m))
    val texts = VerilogModules.split(new String(Files.readAllBytes(d.result.verilog), StandardCharsets.UTF_8))
    val bbFile = d.result.dir.resolve("blackboxes.v")
    val extra = if (Files.isRegularFile(bbFile)) Seq(bbFile) else Seq.empty
    (whole.toSeq.sorted.map(m => (m, false)) ++ shells.toSeq.sorted.map(m => (m, true))).map { case (m, shell) =>
      log(s"timing and power of ${if (shell) s"$m (own logic)" else m} x ${d.inst(m)} ...")
      val files = if (!shell) Seq(d.result.verilog) ++ extra else {
        val f = dir.resolve("sta-shells").resolve(s"$m.v")
        Files.createDirectories(f.getParent)
        val kids = d.own(m).children.distinct.filterNot(d.mems.contains).flatMap(texts.get).map(VerilogModules.shell)
        Files.write(f, (texts(m) +: kids).mkString("\n\n").getBytes(StandardCharsets.UTF_8))
        Seq(f) ++ extra
      }
      val rep = Sta.run(files, m, flow.libPath, flow.clocksGHz, dir.resolve("sta").resolve(m), Seq.empty, Seq.empty, Sta.Activity(meanActivity, 0.5))
      val worst = rep.clocks.head
      Analysis(m, d.inst(m), shell, rep.fmaxGHz, s"${worst.startPoint} -> ${worst.endPoint}") -> rep
    }
  }

  /** The whole design `d` timed at once, so that every path from one part into another is timed
    * ([[Sta.timeWhole]]), or why it could not be (OpenSTA capped at the memory free now, less 1 GB). */
  private def timeWhole(flow: CostFlow, d: Synthesized, dir: Path, log: String => Unit): Either[String, Sta.Whole] = {
    val bbFile = d.result.dir.resolve("blackboxes.v")
    val extra = if (Files.isRegularFile(bbFile)) Seq(bbFile) else Seq.empty
    val free = freeMemoryBytes()
    log(f"timing ${d.top} whole, every path between its parts (OpenSTA capped at ${free / 1e9 - 1}%.1f GB) ...")
    try Right(Sta.timeWhole(Seq(d.result.verilog) ++ extra, d.top, flow.libPath, dir.resolve("sta-whole"),
      memoryLimitBytes = math.max(free - (1L << 30), 1L << 30), progress = m => log(s"  $m")))
    catch { case e: MapmError => Left(e.getMessage) }
  }

  /** The memory the kernel could give a new process now (`MemAvailable`). */
  private def freeMemoryBytes(): Long = {
    val line = new String(Files.readAllBytes(java.nio.file.Paths.get("/proc/meminfo")), StandardCharsets.UTF_8)
      .linesIterator.find(_.startsWith("MemAvailable:"))
    line.map(_.split("\\s+")(1).toLong * 1024).getOrElse(8L << 30)
  }

  /** Method (b)'s figures from the synthesized design `d` and its `analyses`: fmax, logic area,
    * power at each clock, each by block, and the SRAM arrays' bits and modelled area. */
  private def methodB(d: Synthesized, analyses: Seq[(Analysis, Sta.Report)], whole: Either[String, Sta.Whole], p: MapmParams,
                      flow: CostFlow, meanActivity: Double, soa: UnitCost, frame: Option[Frame]): ujson.Obj = {
    val (label, clocks) = (p.counts.label, flow.clocksGHz)
    import d.{own, paths, mems, hier, block}
    val partsFmax = analyses.map(_._1.fmaxGHz).min
    val fmaxB = whole.fold(_ => partsFmax, w => math.min(w.fmaxGHz, partsFmax))
    val slowest = analyses.minBy(_._1.fmaxGHz)._1
    val blocks = CostBlock.all.map(_.name)
    val areaBy = paths.groupBy(block).map { case (b, ps) => b -> ps.map(c => own.get(c.last).map(_.areaUm2).getOrElse(0.0)).sum }
    val seqBy = paths.groupBy(block).map { case (b, ps) => b -> ps.map(c => own.get(c.last).map(_.seqAreaUm2).getOrElse(0.0)).sum }
    val sramBy = paths.filter(c => mems.contains(c.last)).groupBy(block).map { case (b, ps) => b -> ps.map(c => hier.memoryBits(c.last)).sum }
    val rootBlock = analyses.map { case (a, _) => a.root -> block(paths.find(_.last == a.root).getOrElse(Seq(d.top))) }.toMap
    // The SOA, kept whole, takes its power from its own gate-level run (its nets' activity, its
    // stage gates at their duty; the unit flow's figures at the unit's valid rate) instead of the
    // global activity, at which OpenSTA would clock every gated register in every cycle.
    val soaAnalysis = analyses.find { case (a, _) => a.root == soa.top && !a.shell }
    def fromUnit(a: Analysis): Boolean = soaAnalysis.exists(_._1 == a)
    def powerAt(i: Int): (Double, Double, Map[String, Double]) = {
      val per = analyses.map { case (a, rep) =>
        val (dyn, leak) = if (fromUnit(a)) (soa.dynamicMwAt(clocks(i)), soa.clocks.head.leakageMw) else (rep.clocks(i).dynamicMw, rep.clocks(i).leakageMw)
        (rootBlock(a.root), dyn * a.instances, leak * a.instances)
      }
      (per.map(_._2).sum, per.map(_._3).sum, per.groupBy(_._1).map { case (b, xs) => b -> xs.map(_._2).sum })
    }
    val sramBits = sramBy.values.sum
    // Energy per shader operation over the frame, at method (b)'s fmax: the logic's dynamic energy
    // per cycle (its power over its clock, the same at every clock) and leakage over the frame's
    // time, and the SRAM arrays' accesses and leakage (SramEnergy).
    val sramLeakMw = sramBits * SramEnergy.leakageMwPerBit(flow.library)
    val energy: ujson.Value = frame.fold[ujson.Value](ujson.Null) { f =>
      val st = f.stats
      MapmError.check(st.soIssued > 0, s"cost: the frame ${f.path} issued no shader operations")
      val (dyn, leak, _) = powerAt(0)
      val seconds = st.cycles / (fmaxB * 1e9)
      val n = st.soIssued.toDouble
      // The SOAs' share: their energy per operation times the frame's operations (each SO is one
      // SOA operation), so that it follows the frame's own rate rather than the unit run's.
      val soaPerOp = soaAnalysis.flatMap(_ => soa.energyPerOpNj)
      // What powerAt charged the SOAs over the frame's cycles, replaced by their per-operation figure.
      val soaCycleNj = soaAnalysis.filter(_ => soaPerOp.isDefined)
        .fold(0.0) { case (a, _) => soa.dynamicMwAt(clocks.head) * a.instances / clocks.head * st.cycles / 1000.0 }
      val logicNj = dyn / clocks.head * st.cycles / 1000.0 - soaCycleNj + soaPerOp.fold(0.0)(_ * n) + leak * 1e-3 * seconds * 1e9
      val arrays = SramEnergy.arrays(p, st)
      val sramNj = arrays.map(_.dynamicNj).sum + sramLeakMw * 1e-3 * seconds * 1e9
      val soaJson = soaAnalysis.fold[ujson.Value](ujson.Null) { case (a, rep) =>
        ujson.Obj("module" -> a.root, "instances" -> a.instances.toDouble,
          "nJPerSo" -> soaPerOp.map(ujson.Num(_)).getOrElse(ujson.Null),
          "unitValidRate" -> soa.activity.value.get("validRate").getOrElse(ujson.Null),
          "frameValidRate" -> n / (st.cycles.toDouble * a.instances),
          "globalActivityNJPerSo" -> rep.clocks.head.dynamicMw * a.instances / clocks.head * st.cycles / 1000.0 / n)
      }
      ujson.Obj("frame" -> f.path, "clockGHz" -> fmaxB, "cycles" -> st.cycles.toDouble, "shaderOperations" -> n,
        "logic" -> logicNj / n, "sram" -> sramNj / n, "total" -> (logicNj + sramNj) / n, "soa" -> soaJson,
        "sramPowerMw" -> sramNj / seconds * 1e-6,
        "sramByArray" -> ujson.Obj.from(arrays.map(a => a.name -> ujson.Obj("instances" -> a.instances, "depth" -> a.depth.toDouble,
          "width" -> a.width, "reads" -> a.reads.toDouble, "writes" -> a.writes.toDouble, "readPj" -> a.readPj, "nJPerSo" -> a.dynamicNj / n))),
        "note" -> ("logic: the SOAs' energy per operation from their own gate-level run (stage gates at their duty) times the frame's " +
          "operations; every other part's dynamic power at one global activity over its clock, times the frame's cycles; leakage over " +
          "the frame's time at fmax; sram: every array access the frame's counters imply and the arrays' leakage"))
    }
    ujson.Obj(
      "description" -> "every module synthesized once, parts kept whole, own cells x instances; SRAM arrays black-boxed",
      "fmaxGHz" -> fmaxB, "partsFmaxGHz" -> partsFmax, "slowest" -> ujson.Obj("module" -> slowest.root, "path" -> slowest.critical),
      "crossPartTimed" -> whole.isRight,
      "wholeTiming" -> whole.fold(
        why => ujson.Obj("configuration" -> ujson.Null, "reason" -> why),
        w => ujson.Obj("configuration" -> label, "fmaxGHz" -> w.fmaxGHz, "instances" -> w.instances.toDouble, "seconds" -> w.seconds,
          "note" -> "the whole netlist linked and timed at once (ideal clock, a clock tree's transition at every clock pin); SRAM arrays are black boxes, so paths end at their pins and their access time is not counted",
          "trials" -> ujson.Arr.from(w.trials.map { case (p, s) => ujson.Obj("periodNs" -> p, "worstSlackNs" -> s) }),
          "worstPaths" -> ujson.Arr.from(w.worst.map(p => ujson.Obj("start" -> p.startPoint, "end" -> p.endPoint, "slackNs" -> p.slackNs,
            "through" -> ujson.Arr.from(p.through.map(ujson.Str(_)))))))),
      "logicAreaMm2" -> areaBy.values.sum / 1e6, "sequentialAreaMm2" -> seqBy.values.sum / 1e6,
      "areaByBlockMm2" -> ujson.Obj.from(blocks.map(b => b -> ujson.Num(areaBy.getOrElse(b, 0.0) / 1e6))),
      "activity" -> (s"global $meanActivity toggles/cycle (mean net activity of the SOA's gate-level run), duty 0.5" +
        soaAnalysis.fold("")(_ => s"; ${soa.top} at its own gate-level run's figures (its clock gates at their duty)")),
      "clocks" -> ujson.Arr.from(clocks.indices.map { i =>
        val (dyn, leak, by) = powerAt(i)
        ujson.Obj("clockGHz" -> clocks(i), "slackMet" -> (clocks(i) <= fmaxB + 1e-9), "dynamicPowerMw" -> dyn,
          "leakagePowerMw" -> leak, "dynamicByBlockMw" -> ujson.Obj.from(blocks.map(b => b -> ujson.Num(by.getOrElse(b, 0.0)))))
      }),
      "modules" -> ujson.Arr.from(analyses.map { case (a, _) => ujson.Obj("module" -> a.root, "instances" -> a.instances.toDouble,
        "ownLogicOnly" -> a.shell, "fmaxGHz" -> a.fmaxGHz, "criticalPath" -> a.critical,
        "areaUm2" -> (if (a.shell) own(a.root).areaUm2 else 0.0)) }),
      "boundaries" -> {
        val checked = d.comb.toSeq.filter { case (m, _) => m != d.top && !mems.contains(m) && own(m).cells + own(m).children.size > 0 }.sortBy(_._1)
        ujson.Obj("rule" -> ("combinational input-to-output paths of each kept module, through its own cells and its submodules' paths " +
          "(SRAM arrays and flip-flops end a path; configuration inputs io_cfg* are static and left out); " +
          "a module marked registered must have none"),
          "modules" -> ujson.Arr.from(checked.map { case (m, ps) =>
            val counted = ps.filter(p => Boundary.counts(p.from))
            ujson.Obj("module" -> m, "instances" -> d.inst(m).toDouble, "registered" -> d.registered(m), "paths" -> counted.size.toDouble,
              "examples" -> ujson.Arr.from(counted.take(3).map(p => ujson.Str(p.toString))))
          }))
      },
      "sram" -> ujson.Obj("model" -> SramModel.source, "bits" -> sramBits.toDouble,
        "bitsByBlock" -> ujson.Obj.from(blocks.map(b => b -> ujson.Num(sramBy.getOrElse(b, 0L).toDouble))),
        "areaMm2" -> SramModel.areaUm2(sramBits) / 1e6, "leakageMw" -> sramLeakMw,
        "energyModel" -> SramEnergy.source,
        "arrays" -> ujson.Arr.from(mems.map(m => ujson.Obj("module" -> m, "width" -> hier.memories(m)._1,
          "depth" -> hier.memories(m)._2, "instances" -> d.inst.getOrElse(m, 0L).toDouble)))),
      "energyPerSoNj" -> energy)
  }

  /** A render of the configuration whose statistics give the energy per shader operation: its
    * cycles, shader operations and cache counters. */
  final case class Frame(path: String, stats: mapm.sim.HarnessStats)

  /** The frame in `path` (a render's stats.json), checked to be of configuration `p`. */
  def frame(path: Path, p: MapmParams): Frame = {
    MapmError.check(Files.isRegularFile(path), s"cost: frame statistics $path not found (a render's stats.json)")
    val st = mapm.sim.HarnessStats.read(path)
    // The bare MAPM's or the coprocessor's render (the same MAPM, the same counters), full or timing fidelity.
    val tops = for (f <- Fidelity.all; c <- Seq(false, true)) yield MapmRtl.topName(p.copy(sim = p.sim.copy(fidelity = f, coproc = c)))
    MapmError.check(tops.contains(st.top), s"cost: the frame statistics $path are of ${st.top}, not of the costed ${MapmRtl.topName(p)} (render it with the same options)")
    MapmError.check(st.result == "PASS", s"cost: the frame in $path did not pass (${st.failure.getOrElse(st.result)})")
    Frame(path.toString, st)
  }

  /** One OpenSTA analysis: a module (whole, or its own logic in a `shell`), its instances, its
    * fmax and worst path. */
  final case class Analysis(root: String, instances: Long, shell: Boolean, fmaxGHz: Double, critical: String)

  /** The cost of configuration `p` by both methods (the report that cost.json holds): (a) from the
    * SOA's and TSA's unit costs, (b) from `p` synthesized, timed and powered at the flow's clocks
    * with the SOA's mean net activity `meanActivity`; intermediate files under `dir`. */
  def run(flow: CostFlow, p: MapmParams, soa: UnitCost, tsa: UnitCost, meanActivity: Double, dir: Path,
          log: String => Unit, frame: Option[Frame] = None): ujson.Obj = {
    val (nSoa, nTsa) = (p.counts.som * p.counts.soaPerSom, p.counts.tsm)
    val fmaxA = math.min(soa.fmaxGHz, tsa.fmaxGHz)
    val d = synthesize(flow, p, Seq(soa.top), dir, log)
    val t0 = System.nanoTime()
    val analyses = analyse(flow, d, meanActivity, dir, log)
    val whole = timeWhole(flow, d, dir, log)
    val staSecs = (System.nanoTime() - t0) / 1e9
    ujson.Obj(
      "configuration" -> p.counts.label, "format" -> p.numbers.format.toString, "g" -> p.numbers.guardDigits,
      "library" -> flow.libPath.getFileName.toString,
      "methodA" -> ujson.Obj("description" -> s"$nSoa SOAs x ${soa.top} + $nTsa TSAs x ${tsa.top} (dissertation Table 4.9)",
        "fmaxGHz" -> fmaxA, "atFmax" -> methodA(nSoa, nTsa, soa, tsa)(fmaxA), "clocks" -> ujson.Arr.from(flow.clocksGHz.map(methodA(nSoa, nTsa, soa, tsa)))),
      "methodB" -> methodB(d, analyses, whole, p, flow, meanActivity, soa, frame),
      "seconds" -> ujson.Obj("synthesis" -> d.seconds, "sta" -> staSecs))
  }

  /** The tables of a configuration's cost (method a beside method b). */
  def markdown(j: ujson.Obj): String = {
    val a = j("methodA"); val b = j("methodB")
    val sb = new StringBuilder
    sb ++= s"MAPM ${j("configuration").str}, format ${j("format").str}, g = ${j("g").num.toInt}, library ${j("library").str}\n\n"
    sb ++= "| clock (GHz) | (a) slack met? | (a) area (mm^2) | (a) dynamic (mW) | (a) leakage (mW) | (b) slack met? | (b) logic area (mm^2) | (b) dynamic (mW) | (b) leakage (mW) |\n"
    sb ++= "|---:|:---:|---:|---:|---:|:---:|---:|---:|---:|\n"
    for ((ca, cb) <- a("clocks").arr.zip(b("clocks").arr))
      sb ++= f"| ${ca("clockGHz").num}%.3f | ${if (ca("slackMet").bool) "yes" else "no"} | ${ca("areaMm2").num}%.3f | ${ca("dynamicPowerMw").num}%.1f | ${ca("leakagePowerMw").num}%.4f | " +
        f"${if (cb("slackMet").bool) "yes" else "no"} | ${b("logicAreaMm2").num}%.3f | ${cb("dynamicPowerMw").num}%.1f | ${cb("leakagePowerMw").num}%.4f |\n"
    sb ++= f"\n(a) ${a("description").str}: fmax ${a("fmaxGHz").num}%.3f GHz\n"
    sb ++= f"(b) ${b("description").str}: fmax ${b("fmaxGHz").num}%.3f GHz\n"
    sb ++= f"    each part alone: ${b("partsFmaxGHz").num}%.3f GHz (slowest: ${b("slowest")("module").str}, ${b("slowest")("path").str})\n"
    val w = b("wholeTiming")
    sb ++= (if (b("crossPartTimed").bool) f"    timed whole (every path between parts): ${w("fmaxGHz").num}%.3f GHz" +
              w("worstPaths").arr.headOption.fold("")(p => s", worst path ${p("start").str} -> ${p("end").str} through ${p("through").arr.map(_.str).mkString(" > ")}") + "\n"
            else s"    not timed whole, so the paths between parts are not timed: ${w("reason").str}\n")
    sb ++= "    logic area by block (mm^2): " + b("areaByBlockMm2").obj.map { case (k, v) => f"$k ${v.num}%.3f" }.mkString(", ") + "\n"
    val s = b("sram")
    sb ++= f"    SRAM (not synthesized): ${s("bits").num}%.0f bits, ${s("areaMm2").num}%.3f mm^2 by ${s("model").str}\n"
    sb ++= "    SRAM bits by block: " + s("bitsByBlock").obj.map { case (k, v) => f"$k ${v.num}%.0f" }.mkString(", ") + "\n"
    b.obj.get("energyPerSoNj").filter(_ != ujson.Null) match {
      case Some(e) => sb ++= f"    energy per shader operation at ${e("clockGHz").num}%.3f GHz over ${e("frame").str}: logic ${e("logic").num}%.2f nJ, " +
        f"SRAM ${e("sram").num}%.2f nJ, total ${e("total").num}%.2f nJ (SRAM ${e("sramPowerMw").num}%.0f mW)\n" +
        e.obj.get("soa").filter(_ != ujson.Null).fold("")(s => f"      of the logic, the SOAs ${s("nJPerSo").num}%.2f nJ at their own activity " +
          f"(${s("globalActivityNJPerSo").num}%.2f at the global one; valid rate ${s("frameValidRate").num}%.3f in the frame)\n")
      case None => sb ++= "    energy per shader operation: give --frame-stats (a render's stats.json of this MAPM)\n"
    }
    val bounds = b("boundaries")("modules").arr
    sb ++= s"    combinational input-to-output paths: ${bounds.count(_("paths").num > 0)} of ${bounds.size} kept modules have some (" +
      bounds.filter(_("paths").num > 0).map(m => s"${m("module").str} ${m("paths").num.toLong}").mkString(", ") + ")" +
      s"; registered parts: ${bounds.filter(_("registered").bool).map(_("module").str).mkString(", ")}\n"
    sb ++= f"    run time: synthesis ${j("seconds")("synthesis").num}%.0f s, timing and power ${j("seconds")("sta").num}%.0f s\n"
    sb.toString
  }
}
