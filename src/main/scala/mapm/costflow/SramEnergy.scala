package mapm.costflow

import mapm.MapmError
import mapm.cost.Liberty
import mapm.memory.CacheConfig
import mapm.params.MapmParams
import mapm.sim.HarnessStats
import mapm.uncore.Shapes

/** The energy of a MAPM's SRAM arrays over one frame: the caches' tag and data arrays and the
  * Register-queue banks, which method (b) keeps as black boxes (docs/cost.md, "SRAM energy").
  *
  * The arrays come from the configuration's shapes ([[Shapes]]), one per `SyncReadMem` the RTL
  * declares, and how often each is read and written from the frame's counters ([[HarnessStats]]):
  *  - a cache's tag array is read every cycle (its read has no enable: the lookup reads the set of
  *    the request at its input, or its own set again while it stalls) and written once per lookup
  *    (hits plus misses: every lookup writes the set's new tag or replacement state);
  *  - its data array is read once per lookup (a hit at once, a miss or a secondary miss when its
  *    line has come; the read is enabled) and written once per refill beat (a miss's line);
  *  - a Register-queue bank pair is read every cycle (bounded above: both banks read the next top
  *    while the stack holds anything) and written once per pushed child, at most one per TS op.
  * Each access reads or writes a whole row (a tag row holds every way; a data row a whole line;
  * a refill writes one beat of it, masked).
  *
  * Energy per access: Horowitz's published figures for a 64-bit read of an SRAM (ISSCC 2014,
  * "Computing's energy problem", 45 nm, 0.9 V: 8 KB 10 pJ, 32 KB 20 pJ, 1 MB 100 pJ) fit by
  * 10 pJ x sqrt(KB / 8), taken linear in the bits accessed (bit lines and sense amplifiers per
  * bit), a write costing a read, and scaled to 0.18 um and 1.8 V by C x V^2 (4 x 4 = 16).
  * Leakage: a 6T cell's two cross-coupled inverters, twice the library's `INVX1` leakage per bit.
  */
object SramEnergy {
  /** Horowitz (ISSCC 2014): 64-bit reads of 8 KB, 32 KB and 1 MB SRAMs at 45 nm, 0.9 V, in pJ. */
  val Published45nm: Seq[(Double, Double)] = Seq(8.0 -> 10.0, 32.0 -> 20.0, 1024.0 -> 100.0)
  /** C x V^2 from 45 nm, 0.9 V to 0.18 um, 1.8 V: capacitance with the feature size (4x), V^2 (4x). */
  val ScaleTo180nm: Double = (0.18 / 0.045) * (1.8 / 0.9) * (1.8 / 0.9)
  val source: String = "per access: Horowitz ISSCC 2014 64-bit SRAM reads at 45 nm 0.9 V (8 KB 10 pJ, 32 KB 20 pJ, 1 MB 100 pJ) " +
    "fit by 10 pJ x sqrt(KB/8), linear in the bits accessed, a write as a read, x16 to 0.18 um 1.8 V (C x V^2); " +
    "leakage: two INVX1 cells of the library per bit"

  /** A 64-bit access's energy at 45 nm, 0.9 V, in pJ, for an array of `kib` KB (the fit). */
  def pj64At45nm(kib: Double): Double = 10.0 * math.sqrt(kib / 8.0)

  /** One access of `bits` bits to an array of `depth` x `width` bits, in pJ at 0.18 um, 1.8 V. */
  def accessPj(depth: Long, width: Int, bits: Int): Double =
    pj64At45nm(depth * width / 8.0 / 1024.0) * bits / 64.0 * ScaleTo180nm

  /** One kind of SRAM array: `instances` arrays of `depth` x `width` bits, and over the frame all
    * of them together `reads` row reads and `writes` writes of `writeBits` bits each. */
  final case class Array(name: String, depth: Long, width: Int, instances: Int, reads: Long, writes: Long, writeBits: Int) {
    def bits: Long = depth * width * instances
    def readPj: Double = accessPj(depth, width, width)
    def writePj: Double = accessPj(depth, width, writeBits)
    /** The frame's dynamic energy of these arrays, in nJ. */
    def dynamicNj: Double = (reads * readPj + writes * writePj) / 1000.0
  }

  /** The arrays of configuration `p`, depth and width as the RTL declares them, without counts. */
  def arrays(p: MapmParams): Seq[Array] = frame(p, None)

  /** The arrays of `p` with the accesses of the frame `stats` ran (the render's statistics of `p`). */
  def arrays(p: MapmParams, stats: HarnessStats): Seq[Array] = frame(p, Some(stats))

  private def frame(p: MapmParams, stats: Option[HarnessStats]): Seq[Array] = {
    val s = Shapes(p)
    val cycles = stats.fold(0L)(_.cycles)
    def cache(name: String, cfg: CacheConfig, n: Int): Seq[Array] = {
      val (hits, misses) = stats.fold((0L, 0L)) { st =>
        val c = st.caches.getOrElse(name, MapmError.fail(s"cost: the frame's statistics have no counters of the $name cache"))
        (c.hits, c.misses)
      }
      val tagWidth = new mapm.memory.TagRow(cfg).getWidth
      val lineBits = cfg.beatsPerLine * cfg.down.dataBits
      Seq(Array(s"$name tags", 1L << (cfg.setBits max 1), tagWidth, n, cycles * n, hits + misses, tagWidth),
          Array(s"$name data", cfg.hw.lines, lineBits, n, hits + misses, misses * cfg.beatsPerLine, cfg.down.dataBits))
    }
    val t = p.counts.tsm
    val rq = {
      val width = new mapm.tsearch.TsmOp(p).getWidth
      val depth = mapm.tsearch.RegisterStack.bankDepth(p.queues.registerQueueDepth)
      Array("Register queue", depth, width, 2 * t, 2 * cycles * t, stats.flatMap(_.tsOps).getOrElse(0L), width)
    }
    cache("tsL1", s.tsL1, t) ++ cache("soq", s.soq, 1) ++ cache("sopL1", s.sopL1, p.counts.som * p.counts.soaPerSom) ++
      cache("tsL2", s.tsL2, p.uncore.tsL2.banks) ++ cache("sopL2", s.sopL2, p.uncore.sopL2.banks) :+ rq
  }

  /** Leakage of one SRAM bit in mW: a 6T cell's two cross-coupled inverters, twice `INVX1`'s. */
  def leakageMwPerBit(lib: Liberty.Library): Double = {
    val inv = lib.cells.getOrElse("INVX1", MapmError.fail(s"cost: the library ${lib.name} has no INVX1 cell for the SRAM leakage model"))
    2 * inv.leakage * lib.leakageUnitNw * 1e-6
  }
}
