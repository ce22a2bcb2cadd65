// stats.json (docs/harness.md): the run's settings, verdict and counts, the top's counters
// (named by the generated mapm_config.h) and the memory traffic.
#pragma once
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <string>

#include "dram.h"
#include "mapm_config.h"
#include "options.h"
#include "output.h"

// What a run did, besides the DRAM's traffic and the counters.
struct RunSummary {
  std::string failure;
  bool stopped;  // ended at --max-cycles as asked, without a failure
  uint64_t cycles, fed, completed, soOut, soPassed;
  double wallSeconds;
};

// Writes the stats of a run to `path`; false when the file cannot be written.
inline bool writeStats(const std::string& path, const Options& opt, const RunSummary& r, const Dram& dram,
                       const uint64_t* counters, uint64_t passCycles = 0, uint64_t bytesWritten = 0) {
  auto counter = [&](const std::string& n, uint64_t* v) {
    for (int i = 0; i < COUNTER_COUNT; i++) if (n == COUNTER_NAMES[i]) { *v = counters[i]; return true; }
    return false;
  };
  const double cyc = r.cycles ? (double)r.cycles : 1.0;
  Json j;
  j.begin();
  j.str("top", MAPM_TOP_NAME);
  // timing: the SOAs were their timing model; colours and cond (soPassingCond) came from the model.
  j.str("fidelity", MAPM_FIDELITY_TIMING ? "timing" : "full");
  j.str("colourSource", MAPM_FIDELITY_TIMING ? "model" : "rtl");
#ifdef MAPM_COPROC
  // The coprocessor writes the frame itself; its timing model computes no colour.
  j.str("frameSource", MAPM_FIDELITY_TIMING ? "model (timing fidelity)" : "hardware frame buffer");
  j.integer("passCycles", passCycles);
  j.integer("bytesWritten", bytesWritten);
  j.num("frameScale", (double)opt.frameScale);
  j.str("wait", opt.poll ? "polling" : "interrupt");
#else
  j.str("frameSource", "harness accumulation");
  (void)passCycles; (void)bytesWritten;
#endif
  j.begin("config");
  j.integer("tsm", MAPM_TSM);
  j.integer("som", MAPM_SOM);
  j.integer("soaPerSom", MAPM_SOA_PER_SOM);
  j.integer("expWidth", MAPM_EXP_WIDTH);
  j.integer("manWidth", MAPM_MAN_WIDTH);
  j.integer("guardDigits", MAPM_GUARD_DIGITS);
  j.integer("rqDepth", MAPM_RQ_DEPTH);
  j.integer("rsEntries", MAPM_RS_ENTRIES);
  j.integer("memMaxOutstanding", MAPM_MEM_MAX_OUTSTANDING);
  j.end();
  j.str("result", !r.failure.empty() ? "FAIL" : r.stopped ? "STOPPED" : "PASS");
  if (r.failure.empty()) j.null("failure"); else j.str("failure", r.failure);
  j.integer("seed", opt.seed);
  j.integer("latency", opt.latency);
  j.integer("latencyMax", opt.latencyMax ? opt.latencyMax : opt.latency);
  j.num("queryGap", opt.queryGap);
  j.num("reqStall", opt.reqStall);
  j.num("respGap", opt.respGap);
  j.num("tailProb", opt.tailProb);
  j.integer("tailLatency", opt.tailLatency);
  j.str("fault", faultName(opt.fault));
  j.num("bandwidthBytesPerCycle", opt.bandwidth);
  j.num("clockGHz", opt.clockGhz);
  j.integer("cycles", r.cycles);
  j.integer("queries", r.fed);
  j.integer("queriesCompleted", r.completed);
  j.integer("soIssued", r.soOut);
  j.integer("soPassingCond", r.soPassed);
  j.num("soPerCycle", r.soOut / cyc);
  uint64_t ts = 0;
  if (counter("tsOps", &ts)) { j.integer("tsOps", ts); j.num("tsOpsPerCycle", ts / cyc); }
  else { j.null("tsOps"); j.null("tsOpsPerCycle"); }
  j.begin("stallCycles");
  for (int i = 0; i < COUNTER_COUNT; i++)
    if (strncmp(COUNTER_NAMES[i], "stall", 5) == 0) j.integer(COUNTER_NAMES[i], counters[i]);
  j.end();
  j.begin("caches");
  for (int i = 0; i < COUNTER_COUNT; i++) {
    std::string n = COUNTER_NAMES[i];
    const std::string suffix = "_hits";
    if (n.size() <= suffix.size() || n.compare(n.size() - suffix.size(), suffix.size(), suffix) != 0) continue;
    const std::string cache = n.substr(0, n.size() - suffix.size());
    uint64_t misses = 0;
    if (!counter(cache + "_misses", &misses)) continue;
    j.begin(cache);
    j.integer("hits", counters[i]);
    j.integer("misses", misses);
    j.num("hitRate", counters[i] + misses ? (double)counters[i] / (counters[i] + misses) : 0.0);
    j.end();
  }
  j.end();
  j.integer("memoryRequests", dram.requests());
  j.integer("bytesFetched", dram.bytesServed());
  j.num("bytesPerCycle", dram.bytesServed() / cyc);
  j.num("gbPerSecond", dram.bytesServed() / cyc * opt.clockGhz);
  j.begin("counters");
  for (int i = 0; i < COUNTER_COUNT; i++) j.integer(COUNTER_NAMES[i], counters[i]);
  j.end();
  // What each counter counts: the TSMs' stalls are TSM-cycles (summed over the TSMs), so they can exceed `cycles`.
  j.begin("counterUnits");
  for (int i = 0; i < COUNTER_COUNT; i++) j.str(COUNTER_NAMES[i], COUNTER_UNITS[i]);
  j.end();
  j.num("wallSeconds", r.wallSeconds);
  j.num("simulatedCyclesPerSecond", r.cycles / (r.wallSeconds > 0 ? r.wallSeconds : 1e-9));
  j.end();
  FILE* f = fopen(path.c_str(), "w");
  if (!f) return false;
  fputs(j.text().c_str(), f);
  return fclose(f) == 0;
}
