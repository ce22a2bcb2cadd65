package mapm.uncore

import chisel3.util.isPow2
import mapm.memory.{CacheConfig, MemArbiter, MemPortParams}
import mapm.params.MapmParams
import mapm.util.Index

/** Every cache and memory-port shape of one MAPM, derived once from its parameters: the L1s the
  * blocks build (TS L1, SOQ cache, SOP L1 bank), one bank of each L2 the [[Uncore]] builds, and
  * the memory port. The blocks, the uncore, the top and the harness header all take their shapes
  * from here, so a port's width cannot differ between the module that drives it and the one that
  * takes it (the same way constellation turns its user parameters into one validated internal
  * set). Making one checks every cache's constraints (a [[CacheConfig]] `require`s its own).
  */
final class Shapes(p: MapmParams) {
  private val t = p.counts.tsm
  private val clients = p.counts.som * p.counts.soaPerSom

  /** The TS L1 of one TSM: Table 4.2's geometry, one node record per read, one id per fetch slot,
    * whole lines to the TS L2. */
  val tsL1: CacheConfig =
    CacheConfig(p.caches.tsL1, wordBytes = p.records.node.bytes, idBits = Index.bits(p.queues.fetchSlots), addressBits = p.memory.addressBits,
      downBytes = p.caches.tsL1.lineBytes)

  /** The SOQ cache: its geometry, the part of a query record the hardware reads per read, fetched
    * from memory in the port's beats. Every query misses once (its record is read once), so the
    * cache keeps as many misses in flight as there are query fetches (up to its 64 MSHRs): at 100
    * cycles of memory latency, 4 MSHRs would hold the stream to 0.04 queries per cycle. */
  val soq: CacheConfig = {
    val n = p.queues.queryFetches
    CacheConfig(p.caches.soq, wordBytes = p.records.queryHwBytes, idBits = Index.bits(n), addressBits = p.memory.addressBits,
      downBytes = p.memory.dataBytes, mshrs = n min 64, targets = n min 64)
  }

  /** One SOP L1 bank ([[MapmParams.sopL1Bank]]), one per SOA: one photon record per read, one id
    * per reservation-station entry of its lane; interleaved with its SOM's other banks by record
    * when a record fills a line and the SOA count is a power of two. */
  val sopL1: CacheConfig = {
    val g = p.sopL1Bank
    val a = p.counts.soaPerSom
    val record = p.records.photon.bytes
    val interleave = if (isPow2(a) && g.lineBytes == record) a else 1
    CacheConfig(g, wordBytes = record, idBits = Index.bits(p.rsPerSoa), addressBits = p.memory.addressBits, downBytes = g.lineBytes,
      interleave = interleave)
  }

  /** One bank of the TS L2 (the whole TS L2 when shared) under the TSMs' L1s. */
  val tsL2: CacheConfig = l2Bank(tsL1, t, p.tsL2Bank, p.uncore.tsL2.banks)

  /** One bank of the SOP L2 (the whole SOP L2 when shared) under the SOP L1 banks. */
  val sopL2: CacheConfig = l2Bank(sopL1, clients, p.sopL2Bank, p.uncore.sopL2.banks)

  /** The memory arbiter's clients in port order: the TS L2's banks, the SOQ cache, the SOP L2's banks. */
  val memClients: Seq[MemPortParams] =
    Seq.fill(p.uncore.tsL2.banks)(tsL2.down) ++ Seq(soq.down) ++ Seq.fill(p.uncore.sopL2.banks)(sopL2.down)

  /** The MAPM's memory port: the memory arbiter's, over [[memClients]]. */
  val mem: MemPortParams = MemArbiter.downParams(memClients)

  /** A bank of an L2 of `banks` banks serving `clients` L1s of `l1`'s shape through their arbiter,
    * fetching from memory in the port's beats. */
  private def l2Bank(l1: CacheConfig, clients: Int, geometry: mapm.params.CacheParams, banks: Int): CacheConfig =
    CacheConfig.below(MemArbiter.downParams(Seq.fill(clients)(l1.down)), geometry, downBytes = p.memory.dataBytes).copy(interleave = banks)
}

object Shapes {
  /** The shapes of `p`. */
  def apply(p: MapmParams): Shapes = new Shapes(p)
}
