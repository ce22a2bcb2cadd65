package mapm.top

import mapm.params._
import chisel3._
import chisel3.util._
import mapm.memory.{MemArbiter, MemPort, MemPortParams}
import mapm.shader.SoBlock
import mapm.tsearch.{QueryFetch, TsBlock}
import mapm.util.Pick

/** The whole Multi-Accelerator for Photon Mapping (3.2, docs/mapm.md): the Tree Search block
  * ([[TsBlock]]: query stream, SOQ cache, Launcher, TSMs with TS L1s, TSAs, Nextnode and the
  * Register queue, TS L2), the Shader Operation block ([[SoBlock]]: Data bus, SOMs with
  * reservation stations, SOP L1 banks and SOAs, SOP L2), and one memory port shared by the TS L2,
  * the SOQ cache and the SOP L2 through a [[MemArbiter]] that keeps at most
  * `memory.maxOutstanding` requests in flight.
  *
  * The host sets `cfg` before the first query, feeds tree-search instructions on `query`, plays
  * DRAM on `mem` (read only), collects every shader operation's result on `out` (one port per
  * SOA; the results whose cond holds are the colour to add to the query's pixel), and waits for
  * `done` after its last query: every accepted query finished, nothing in flight anywhere, no
  * memory request outstanding. `error` is sticky (a malformed node record, an invalid TSA input,
  * a cache protocol error or a Register-queue overflow; none can happen on a model-built image).
  *
  * Latency: variable (memory, stalls); a query's first SO leaves after about 3 (SOQ) + 4 + TSA +
  * 1 + 4 + SOA latency cycles on cache hits. Throughput: one tree-search operation per TSM and one
  * shader operation per SOA per cycle.
  */
class Mapm(val p: MapmParams) extends Module {
  override def desiredName = s"Mapm_${p.name}"
  val memParams: MemPortParams = Mapm.memParams(p)

  val io = IO(new Bundle {
    val cfg = Input(new MapmConfig(p))
    val query = Flipped(Decoupled(new QueryIn(p)))
    val mem = new MemPort(memParams)
    val out = Output(Vec(p.counts.som * p.counts.soaPerSom, Valid(new SoResult(p))))
    val done = Output(Bool())
    val error = Output(Bool())
    val counters = Output(new MapmCounters)
  })

  val ts = Module(new TsBlock(p))
  val so = Module(new SoBlock(p))
  ts.io.cfg := io.cfg
  so.io.cfg := io.cfg
  ts.io.query <> io.query
  so.io.in <> ts.io.so
  io.out := so.io.out

  val arb = Module(new MemArbiter(Seq(ts.io.tsMem.p, ts.io.soqMem.p, so.io.mem.p), p.memory.maxOutstanding))
  arb.io.up(0) <> ts.io.tsMem
  arb.io.up(1) <> ts.io.soqMem
  arb.io.up(2) <> so.io.mem
  io.mem <> arb.io.down

  // Requests outstanding on the memory port (request taken to last beat).
  val outstanding = RegInit(0.U(log2Ceil(p.memory.maxOutstanding + 1).W))
  outstanding := outstanding + io.mem.req.fire.asUInt - (io.mem.resp.fire && io.mem.resp.bits.last).asUInt
  io.done := ts.io.idle && so.io.idle && outstanding === 0.U
  val error = RegInit(false.B)
  when(ts.io.error || so.io.error) { error := true.B }
  io.error := error

  val c = io.counters
  private val tc = ts.io.counters
  private val sc = so.io.counters
  c.cycles := Pick.counter(Seq(true.B))
  c.queries := Pick.counter(Seq(io.query.fire))
  c.tsOps := tc.tsOps
  c.soIssued := sc.soIssued
  c.soPassed := sc.soPassed
  c.stallNodeData := tc.stallNodeData
  c.stallRsFull := tc.stallRsFull
  c.stallRqFull := tc.stallRqFull
  c.stallQuery := tc.stallQuery
  c.tsL1_hits := tc.tsL1Hits
  c.tsL1_misses := tc.tsL1Misses
  c.tsL2_hits := tc.tsL2Hits
  c.tsL2_misses := tc.tsL2Misses
  c.soq_hits := tc.soqHits
  c.soq_misses := tc.soqMisses
  c.sopL1_hits := sc.sopL1Hits
  c.sopL1_misses := sc.sopL1Misses
  c.sopL2_hits := sc.sopL2Hits
  c.sopL2_misses := sc.sopL2Misses
  c.bytesFetched := (Pick.counter(Seq(io.mem.resp.fire)) << log2Ceil(p.memory.dataBytes))(63, 0)
  c.rqPeak := tc.rqPeak
}

object Mapm {
  /** [[configHeader]] for this generator's own top, `Mapm_<p.name>`. */
  def configHeader(p: MapmParams): String = configHeader(p, s"Mapm_${p.name}")

  /** `mapm_config.h`, the one header a C++ harness needs for configuration `p` whose top module is
    * `top` (Verilated as class `V<top>`), derived from the parameters alone: the parameters as
    * `MAPM_*` constants, accessors for the top's ports (widths and port counts follow from `p`) and
    * the counters ([[MapmCounters.Names]]). tools/harness holds nothing that differs between
    * configurations. */
  def configHeader(p: MapmParams, topName: String): String = {
    val mem = memParams(p)
    val fmt = p.numbers.format
    val outs = p.counts.som * p.counts.soaPerSom
    val defs = Seq(
      "TSM" -> p.counts.tsm, "SOM" -> p.counts.som, "SOA_PER_SOM" -> p.counts.soaPerSom,
      "OUT_PORTS" -> outs, "EXP_WIDTH" -> fmt.expWidth, "MAN_WIDTH" -> fmt.manWidth,
      "FORMAT_WIDTH" -> fmt.width, "GUARD_DIGITS" -> p.numbers.guardDigits,
      "RQ_DEPTH" -> p.queues.registerQueueDepth, "RS_ENTRIES" -> p.queues.rsEntries, "FETCH_SLOTS" -> p.queues.fetchSlots,
      "TSM_QUERIES" -> p.queues.tsmQueries, "QUERY_FETCHES" -> p.queues.queryFetches,
      "ADDRESS_BITS" -> mem.addressBits, "MEM_DATA_BYTES" -> mem.dataBytes, "MEM_ID_BITS" -> mem.idBits,
      "MEM_MAX_BEATS" -> mem.maxBeats, "MEM_MAX_OUTSTANDING" -> p.memory.maxOutstanding,
      "QUERY_BITS" -> p.indices.queryBits, "NODE_BITS" -> p.indices.nodeBits)
    // Verilator holds ports of more than 64 bits as arrays of 32-bit words.
    val data =
      if (mem.dataBytes > 8) (0 until mem.dataBytes / 4).map(i => s"  { uint32_t w; memcpy(&w, d + ${4 * i}, 4); t->io_mem_resp_bits_data[$i] = w; }")
      else Seq(s"  { uint64_t w = 0; memcpy(&w, d, ${mem.dataBytes}); t->io_mem_resp_bits_data = w; }")
    val readOuts = (0 until outs).map { k =>
      val b = s"t->io_out_${k}_bits_"
      s"""  o[$k].valid = t->io_out_${k}_valid;
         |  if (o[$k].valid) {
         |    o[$k].colour[0] = ${b}colour_0; o[$k].colour[1] = ${b}colour_1; o[$k].colour[2] = ${b}colour_2;
         |    o[$k].flags[0] = ${b}flags_0; o[$k].flags[1] = ${b}flags_1; o[$k].flags[2] = ${b}flags_2;
         |    o[$k].cond = ${b}cond; o[$k].q = ${b}q; o[$k].photon = ${b}photon;
         |  }""".stripMargin
    }
    val names = MapmCounters.Names
    s"""// Generated by mapm.top.Mapm.configHeader for $topName: do not edit.
       |#pragma once
       |#include <cstdint>
       |#include <cstring>
       |#include "V$topName.h"
       |typedef V$topName Top;
       |#define MAPM_TOP_NAME "$topName"
       |${defs.map { case (k, v) => s"#define MAPM_$k $v" }.mkString("\n")}
       |struct OutBeat { bool valid; uint64_t colour[3]; uint32_t flags[3]; bool cond; uint64_t q, photon; };
       |static inline void setConfig(Top* t, uint64_t h, uint64_t nodeBase, uint64_t photonBase, uint64_t queryBase, uint64_t nodeCount) {
       |  t->io_cfg_h = h; t->io_cfg_nodeBase = nodeBase; t->io_cfg_photonBase = photonBase;
       |  t->io_cfg_queryBase = queryBase; t->io_cfg_nodeCount = nodeCount;
       |}
       |static inline void setQuery(Top* t, bool v, uint64_t x, uint64_t y, uint64_t z, uint64_t q) {
       |  t->io_query_valid = v; t->io_query_bits_x = x; t->io_query_bits_y = y; t->io_query_bits_z = z; t->io_query_bits_q = q;
       |}
       |static inline bool queryReady(Top* t) { return t->io_query_ready; }
       |static inline bool memReqValid(Top* t) { return t->io_mem_req_valid; }
       |static inline uint64_t memReqAddr(Top* t) { return t->io_mem_req_bits_addr; }
       |static inline uint64_t memReqId(Top* t) { return t->io_mem_req_bits_id; }
       |static inline uint64_t memReqLen(Top* t) { return t->io_mem_req_bits_len; }
       |static inline void setMemReqReady(Top* t, bool r) { t->io_mem_req_ready = r; }
       |static inline bool memRespReady(Top* t) { return t->io_mem_resp_ready; }
       |static inline void setMemResp(Top* t, bool v, const uint8_t* d, uint64_t id, bool last) {
       |  t->io_mem_resp_valid = v; t->io_mem_resp_bits_id = id; t->io_mem_resp_bits_last = last;
       |${data.mkString("\n")}
       |}
       |static inline bool doneOut(Top* t) { return t->io_done; }
       |static inline bool errorOut(Top* t) { return t->io_error; }
       |static inline void readOuts(Top* t, OutBeat* o) {
       |${readOuts.mkString("\n")}
       |}
       |static const int COUNTER_COUNT = ${names.size};
       |static const char* const COUNTER_NAMES[] = {${(names.map(n => "\"" + n + "\"") :+ "nullptr").mkString(", ")}};
       |static inline void readCounters(Top* t, uint64_t* v) {
       |${names.zipWithIndex.map { case (n, i) => s"  v[$i] = t->io_counters_$n;" }.mkString("\n")}
       |}
       |""".stripMargin
  }

  /** The shape of the top's memory port: the outer arbiter's shared port over the TS L2, the SOQ
    * cache and the SOP L2. */
  def memParams(p: MapmParams): MemPortParams =
    MemArbiter.downParams(Seq(TsBlock.l2Config(p).down, QueryFetch.soqConfig(p).down, SoBlock.l2Config(p).down))
}
