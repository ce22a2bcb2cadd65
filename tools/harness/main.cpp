// Verilator harness for the whole MAPM (docs/harness.md): feeds the query stream of a memory
// image through io_query, plays DRAM on io_mem, checks every io_out result against the expected
// shader operations, accumulates the passing colours into their pixels exactly, and writes the
// frame and a stats JSON. Ends with one line: `PASS seed=N` or `FAIL seed=N: reason`.
//
// Nothing here depends on the configuration: mapm_config.h (generated from the parameters by
// mapm.sim.HarnessHeader) names the Verilated top and gives its port accessors and counters,
// and mapm_formats.h (mapm.format.CHeader) the file records.
#include <chrono>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <random>
#include <string>
#include <vector>

#include "check.h"
#include "dram.h"
#include "expected.h"
#include "fault.h"
#include "image.h"
#include "mapm_config.h"
#include "options.h"
#include "output.h"
#include "stats.h"
#include "step.h"

// Under `valgrind --tool=callgrind --instr-atstart=no`, --measure-from N switches callgrind's
// instrumentation on at cycle N and off when the cycle loop ends, so its count is that of the
// cycles between alone (mapm bench-sim). Outside valgrind these are a few no-op instructions.
#if __has_include(<valgrind/callgrind.h>)
#include <valgrind/callgrind.h>
#define MEASURE_START() CALLGRIND_START_INSTRUMENTATION
#define MEASURE_STOP() CALLGRIND_STOP_INSTRUMENTATION
#else
#define MEASURE_START() ((void)0)
#define MEASURE_STOP() ((void)0)
#endif

int main(int argc, char** argv) {
  const auto wall0 = std::chrono::steady_clock::now();
  const Options opt = parseOptions(argc, argv);
  Image img;
  Expected exp;
  std::string failure;
  auto fatal = [&](const std::string& m) { printf("FAIL seed=%llu: %s\n", (unsigned long long)opt.seed, m.c_str()); exit(1); };
  if (!(failure = img.load(opt.image, MAPM_EXP_WIDTH, MAPM_MAN_WIDTH, MAPM_SLOT_BYTES)).empty()) fatal(failure);
  if (!(failure = exp.load(opt.expected, img.queries)).empty()) fatal(failure);
  if (axiOnly(opt.fault)) fatal(std::string("--fault ") + faultName(opt.fault) + " is the coprocessor's (its AXI4 port): run with --coproc");
  if (!(failure = corruptImage(opt.fault, img)).empty()) fatal(failure);
  if (exp.ew != img.ew || exp.mw != img.mw) fatal("the expected-SO file and the image use different formats");
  const uint64_t pixels = (uint64_t)exp.width * exp.height;
  for (uint32_t q = 0; q < img.queries; q++)
    if (img.pixel(q) >= pixels) fatal("query " + std::to_string(q) + " has pixel " + std::to_string(img.pixel(q)) + " outside the image");
#if !VM_TRACE
  if (!opt.wave.empty()) fatal("--wave needs a harness built with --trace-fst");
#endif

  Bench bench(argc, argv, opt);
  bench.reset(img);
  Dram dram(img.bytes, img.readable(), MAPM_MEM_DATA_BYTES, opt.latency, opt.latencyMax ? opt.latencyMax : opt.latency, opt.bandwidth, opt.respGap,
            opt.seed, opt.tailProb, opt.tailLatency);
  ResponseFault respFault(opt.fault, opt.faultAt, MAPM_MEM_ID_BITS);
  // Host-side randomness (query-stream gaps, request back-pressure), apart from the DRAM's.
  std::mt19937_64 host(opt.seed * 0x9e3779b97f4a7c15ull + 1);
  std::uniform_real_distribution<double> coin(0.0, 1.0);
  Checker check(exp, img, pixels);
  // --results: one line "cycle port q photon" per result beat, in the order they came out.
  FILE* results = opt.results.empty() ? nullptr : fopen(opt.results.c_str(), "w");
  if (!opt.results.empty() && !results) fatal("cannot write " + opt.results);
  uint8_t beat[MAPM_MEM_DATA_BYTES] = {0};
  uint64_t fed = 0, lastActivity = 0;
  bool stopped = false;
  auto lastProgress = std::chrono::steady_clock::now();
  auto progress = [&] {
    fprintf(stderr, "progress %llu %u %llu\n", (unsigned long long)check.completed, img.queries, (unsigned long long)bench.cycle());
  };

  while (failure.empty()) {
    const uint64_t cycle = bench.cycle();
    if (cycle == opt.measureFrom) MEASURE_START();
    Drive d;
    d.queryValid = fed < img.queries && !(opt.queryGap > 0 && coin(host) < opt.queryGap);
    d.reqReady = !(opt.reqStall > 0 && coin(host) < opt.reqStall);
    if (d.queryValid) {
      const uint32_t k = (uint32_t)fed;
      d.q = img.streamQuery(k);
      if (opt.fault == Fault::QueryIndex && k == 0) d.q = img.queries + 1000;
    }
    d.respValid = dram.present(cycle, beat, &d.respId, &d.respLast);
    const bool faultBeat = respFault.inject(cycle, dram, beat, MAPM_MEM_DATA_BYTES, &d.respId, &d.respLast);
    d.respValid = d.respValid || faultBeat;
    d.respData = beat;
    const Sample s = bench.drive(d);
    if (fed == img.queries && s.done) {
      if (dram.outstanding()) failure = "io_done high with " + std::to_string(dram.outstanding()) + " memory requests outstanding";
      break;
    }
    const bool qFire = d.queryValid && s.queryReady;
    const bool reqFire = d.reqReady && s.reqValid;
    const bool respFire = d.respValid && s.respReady;
    bench.rise();
    // Apply the cycle's handshakes and results.
    if (qFire) { check.taken(img.streamQuery((uint32_t)fed)); fed++; }
    if (reqFire) failure = dram.request(cycle, s.reqAddr, s.reqId, s.reqLen);
    if (respFire && !faultBeat) dram.taken();
    bool anyOut = false;
    for (int p = 0; p < MAPM_OUT_PORTS && failure.empty(); p++) {
      if (!s.out[p].valid) continue;
      anyOut = true;
      failure = check.beat(s.out[p], p, cycle);
      if (results)
        fprintf(results, "%llu %d %llu %llu\n", (unsigned long long)cycle, p, (unsigned long long)s.out[p].q,
                (unsigned long long)s.out[p].photon);
    }
    if (qFire || reqFire || respFire || anyOut) lastActivity = cycle;
    if (failure.empty() && s.error) failure = "io_error raised at cycle " + std::to_string(cycle);
    bench.endCycle();
    // --max-cycles: a stop asked for, not a failure: what came out is checked, the rest is not run.
    if (failure.empty() && opt.maxCycles && bench.cycle() >= opt.maxCycles) { stopped = true; break; }
    if (failure.empty() && bench.cycle() - lastActivity > opt.idleCycles)
      failure = "watchdog: no handshake or result for " + std::to_string(opt.idleCycles) + " cycles";
    if ((bench.cycle() & 4095) == 0) {
      auto now = std::chrono::steady_clock::now();
      if (now - lastProgress > std::chrono::milliseconds(500)) {
        lastProgress = now;
        progress();
        fflush(stderr);
      }
    }
  }
  if (bench.cycle() > opt.measureFrom) MEASURE_STOP();
  progress();
  if (!stopped) {
    if (failure.empty() && fed < img.queries) failure = "done before every query was fed";
    if (failure.empty()) failure = check.missing();
    if (failure.empty() && opt.fault != Fault::None) failure = std::string("the injected fault was not flagged");
  }
  if (!failure.empty() && opt.fault != Fault::None)
    failure += std::string(" (injected fault: ") + faultName(opt.fault) +
               (respFault.injected() ? " at cycle " + std::to_string(respFault.cycle()) : std::string()) + ")";
  bench.finish();
  if (results && fclose(results) != 0) fatal("cannot write " + opt.results);

  std::vector<double> rgb(3 * pixels);
  for (uint64_t i = 0; i < rgb.size(); i++) rgb[i] = check.acc.toDouble(i);
  const std::string out = opt.out + "/";
  if (!writePfm(out + "frame.pfm", rgb, exp.width, exp.height) || !writeDoubles(out + "frame.f64", rgb))
    fatal("cannot write the frame into " + opt.out);
  const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - wall0).count();
  uint64_t counters[COUNTER_COUNT + 1];
  bench.counters(counters);
  const RunSummary run{failure, stopped, bench.cycle(), fed, check.completed, check.soOut, check.soPassed, wall};
  if (!writeStats(out + "stats.json", opt, run, dram, counters)) fatal("cannot write " + out + "stats.json");
  if (!failure.empty()) fatal(failure);
  if (stopped) {
    printf("STOPPED at cycle %llu as asked (--max-cycles %llu): %llu of %u queries complete, %llu results out, each checked%s; the rest not run\n",
           (unsigned long long)bench.cycle(), (unsigned long long)opt.maxCycles, (unsigned long long)check.completed, img.queries,
           (unsigned long long)check.soOut,
           MAPM_FIDELITY_TIMING ? " ((q, photon) against the model)" : " bit-exact against the model");
    return 0;
  }
  printf("PASS seed=%llu%s\n", (unsigned long long)opt.seed,
         MAPM_FIDELITY_TIMING ? " (timing model: (q, photon), counts and cycles checked; colours from the model)" : "");
  return 0;
}
