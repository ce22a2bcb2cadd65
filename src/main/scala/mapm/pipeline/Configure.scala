package mapm.pipeline

import mapm.format.SlotLayout
import mapm.numerics.{Arith, FloatFormat}
import mapm.params._

/** A cache geometry asked for on the command line, `SIZE[/LINE[/WAYS]]` (e.g. `32K/32/4`,
  * `512K/64/full`, `8K`): each part not given keeps the default's, and a default that is fully
  * associative stays so when only the size changes. */
final case class CacheSpec(
    sizeBytes: Option[Int] = None, // total data bytes
    lineBytes: Option[Int] = None, // bytes per line
    ways: Option[Int] = None       // associativity; CacheSpec.Full = fully associative
) {
  /** The default `base` with the parts given here. */
  def applyTo(base: CacheParams): CacheParams = {
    val size = sizeBytes.getOrElse(base.sizeBytes)
    val line = lineBytes.getOrElse(base.lineBytes)
    val w = ways match {
      case Some(CacheSpec.Full) => size / line
      case Some(n)              => n
      case None                 => if (base.fullyAssociative) size / line else base.ways
    }
    CacheParams(size, line, w)
  }
  def isEmpty: Boolean = sizeBytes.isEmpty && lineBytes.isEmpty && ways.isEmpty
  /** The parts given, as [[CacheSpec.parse]] reads them back (`32768/32/full`); empty when none is. */
  def text: String = Seq(sizeBytes.map(_.toString), lineBytes.map(_.toString), ways.map(w => if (w == CacheSpec.Full) "full" else w.toString)).flatten.mkString("/")
}

object CacheSpec {
  /** `ways` value for a fully associative cache. */
  val Full: Int = -1

  /** Parses `SIZE[/LINE[/WAYS]]`; SIZE in bytes with an optional K or M suffix, WAYS a count or `full`. */
  def parse(s: String): CacheSpec = {
    def fail(why: String): Nothing = mapm.MapmError.fail(s"cache geometry '$s': $why (SIZE[/LINE[/WAYS]], e.g. 32K/32/4 or 512K/64/full)")
    def bytes(t: String): Int = {
      val (num, mul) = t.trim.toUpperCase match {
        case x if x.endsWith("K") => (x.dropRight(1), 1024L)
        case x if x.endsWith("M") => (x.dropRight(1), 1024L * 1024)
        case x                    => (x, 1L)
      }
      num.toLongOption.map(_ * mul).filter(v => v > 0 && v <= Int.MaxValue).map(_.toInt).getOrElse(fail(s"'$t' is not a positive byte count"))
    }
    s.split("/", -1).toSeq match {
      case Seq(size) => CacheSpec(Some(bytes(size)))
      case Seq(size, line) => CacheSpec(Some(bytes(size)), Some(bytes(line)))
      case Seq(size, line, w) =>
        val ways = if (w.trim.equalsIgnoreCase("full")) Full
          else w.trim.toIntOption.filter(_ >= 1).getOrElse(fail(s"ways '$w' is not a count >= 1 or 'full'"))
        CacheSpec(Some(bytes(size)), Some(bytes(line)), Some(ways))
      case _ => fail("too many parts")
    }
  }
}

/** The memory hierarchy and the sizes Table 4.2 and the design space vary, as the command line
  * gives them (`--hierarchy`, `--rq-depth`, `--rs-entries`, `--ts-l1` ... `--sop-l2`,
  * `--mem-outstanding`, `--ts-l2-banks`, `--sop-l2-banks`); each absent size keeps the
  * hierarchy's. */
final case class Tuning(
    registerQueueDepth: Option[Int] = None, // entries of each TSM's Register-queue bank
    rsEntries: Option[Int] = None,          // reservation-station entries per SOM
    tsL1: CacheSpec = CacheSpec(),          // TS L1 geometry
    tsL2: CacheSpec = CacheSpec(),          // TS L2 geometry
    soq: CacheSpec = CacheSpec(),           // SOQ geometry
    sopL1: CacheSpec = CacheSpec(),         // SOP L1 geometry (per SOM, split into one bank per SOA)
    sopL2: CacheSpec = CacheSpec(),         // SOP L2 geometry
    memOutstanding: Option[Int] = None,     // requests in flight on the memory port
    soaClockGate: Boolean = true,           // gate each SOA's clock while it holds no operation
    sopL2Banks: Option[Int] = None,         // SOP L2 banks (1: one shared cache, Table 4.2's)
    tsL2Banks: Option[Int] = None,          // TS L2 banks (1: one shared cache, Table 4.2's)
    hierarchy: Hierarchy = Hierarchy.Scalable, // the memory hierarchy the sizes start from
    coproc: Boolean = false,                // run the coprocessor (docs/coprocessor.md) rather than the bare MAPM
    frameBanks: Option[Int] = None,         // the coprocessor's accumulator banks
    resultFifo: Option[Int] = None,         // the coprocessor's result FIFO entries per SOA
    streamLines: Option[Int] = None,        // the coprocessor's query-stream lines read ahead
    soBus: Option[SoBus] = None,            // the Data bus (None: the hierarchy's)
    soaStageGate: Boolean = true            // gate each SOA pipeline stage's clock while it takes no operation
) {
  /** The overrides given, as `name=value` words (empty for none), for logs and CSVs. */
  def describe: Seq[String] = {
    def spec(n: String, c: CacheSpec) = if (c.isEmpty) None else Some(s"$n=${c.text}")
    registerQueueDepth.map(d => s"rq-depth=$d").toSeq ++ rsEntries.map(r => s"rs-entries=$r") ++
      Seq("ts-l1" -> tsL1, "ts-l2" -> tsL2, "soq" -> soq, "sop-l1" -> sopL1, "sop-l2" -> sopL2).flatMap { case (n, c) => spec(n, c) } ++
      memOutstanding.map(m => s"mem-outstanding=$m") ++ (if (soaClockGate) None else Some("no-soa-clock-gate")) ++
      (if (soaStageGate) None else Some("no-soa-stage-gate")) ++
      sopL2Banks.map(b => s"sop-l2-banks=$b") ++ tsL2Banks.map(b => s"ts-l2-banks=$b") ++
      (if (hierarchy == Hierarchy.Scalable) None else Some(s"hierarchy=$hierarchy")) ++ (if (coproc) Some("coproc") else None) ++
      frameBanks.map(b => s"frame-banks=$b") ++ resultFifo.map(f => s"result-fifo=$f") ++ streamLines.map(l => s"stream-lines=$l") ++
      soBus.map(b => s"so-bus=$b")
  }

  /** The hierarchy and the sizes given, in a phrase for a log or a report. */
  def summary: String = {
    val h = s"the $hierarchy memory hierarchy${if (hierarchy == Hierarchy.Table42) "" else " (docs/uncore.md)"}"
    val sizes = describe.filterNot(_.startsWith("hierarchy="))
    if (sizes.isEmpty) s"$h, Table 4.2's capacities" else s"$h with ${sizes.mkString(", ")}"
  }
}

/** A MAPM configuration made from what a command line gives: counts, format, guard digits, layout,
  * arithmetic, fidelity and the sizes it overrides ([[Tuning]]). */
object Configure {
  /** The L2 of `--ts-l2-banks n` or `--sop-l2-banks n` (`flag`): shared for 1, else `n` banks; a
    * [[mapm.MapmError]] naming the option for a count the hardware does not build. */
  def l2Structure(flag: String, n: Int): L2Structure =
    if (n == 1) L2Structure.Shared
    else try L2Structure.Banked(n)
    catch { case e: IllegalArgumentException => mapm.MapmError.fail(s"--$flag: ${e.getMessage.stripPrefix("requirement failed: ")}") }

  /** The configuration a command line asks for: module counts, format, guard digits and memory
    * layout, the memory hierarchy `tuning` names and the sizes it overrides (queues, caches, L2
    * banks, the memory port); everything else as [[MapmParams.table48]] sizes it, with every
    * cache line at least as long as the record it holds (a 64-byte photon record of 8-byte slots
    * takes 64-byte SOP L1 lines). A broken constraint is a one-line [[mapm.MapmError]] naming
    * it, not an exception. */
  def of(tsm: Int, som: Int, soa: Int, format: FloatFormat, g: Int, layout: SlotLayout = SlotLayout.Packed,
         arith: Arith = Arith.Online, fidelity: Fidelity = Fidelity.Full, tuning: Tuning = Tuning()): MapmParams =
    try {
      val h = tuning.hierarchy
      val base = MapmParams.table48(tsm, som, soa)
      val r = new Records(layout.slotBytes(format))
      // A default line too short for its record grows to fit; a line the user gave is checked as given.
      // A geometry that breaks a cache's own constraint names the option that gave it.
      def fit(flag: String, c: CacheParams, spec: CacheSpec, bytes: Int) =
        try {
          val grown = if (spec.lineBytes.isEmpty && c.lineBytes < bytes) c.copy(lineBytes = bytes) else c
          spec.applyTo(grown)
        } catch { case e: IllegalArgumentException => throw new IllegalArgumentException(s"--$flag: ${e.getMessage.stripPrefix("requirement failed: ")}") }
      val c = base.caches
      val t = tuning
      val sopL2 = fit("sop-l2", c.sopL2, t.sopL2, 0)
      val bus = t.soBus.getOrElse(h.uncore(base.counts, sopL2).soBus)
      base.copy(
        numbers = NumberParams(format, g, arith = arith),
        memory = base.memory.copy(layout = layout, maxOutstanding = t.memOutstanding.getOrElse(base.memory.maxOutstanding)),
        sim = SimParams(fidelity, t.coproc),
        coproc = base.coproc.copy(banks = t.frameBanks.getOrElse(base.coproc.banks), laneFifo = t.resultFifo.getOrElse(base.coproc.laneFifo),
          streamLines = t.streamLines.getOrElse(base.coproc.streamLines)),
        clocking = ClockingParams(t.soaClockGate, t.soaStageGate),
        uncore = {
          // The hierarchy's L2 structures for the SOP L2 as given, each bank count given in their place.
          val u = h.uncore(base.counts, sopL2)
          u.copy(tsL2 = t.tsL2Banks.map(l2Structure("ts-l2-banks", _)).getOrElse(u.tsL2),
            sopL2 = t.sopL2Banks.map(l2Structure("sop-l2-banks", _)).getOrElse(u.sopL2), soBus = bus)
        },
        caches = CachesParams(tsL1 = fit("ts-l1", h.tsL1, t.tsL1, r.node.bytes), tsL2 = fit("ts-l2", c.tsL2, t.tsL2, 0),
          soq = fit("soq", h.soq, t.soq, r.queryHwBytes), sopL1 = fit("sop-l1", c.sopL1, t.sopL1, r.photon.bytes),
          sopL2 = sopL2),
        queues = base.queues.copy(registerQueueDepth = t.registerQueueDepth.getOrElse(base.queues.registerQueueDepth),
          rsEntries = t.rsEntries.getOrElse(base.queues.rsEntries + bus.extraRsPerSoa * soa)))
    } catch {
      case e: IllegalArgumentException => mapm.MapmError.fail(s"configuration ${tsm}/${som}/${soa} ${format.name}: ${e.getMessage.stripPrefix("requirement failed: ")}")
    }
}
