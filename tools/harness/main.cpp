// Verilator harness for the whole MAPM (docs/harness.md): feeds the query stream of a memory
// image through io_query, plays DRAM on io_mem, checks every io_out result against the expected
// shader operations, accumulates the passing colours into their pixels exactly, and writes the
// frame and a stats JSON. Ends with one line: `PASS seed=N` or `FAIL seed=N: reason`.
//
// mapm_ports.h is generated per configuration by mapm.sim.Harness: it names the Verilated top
// class and gives typed accessors for its ports (widths differ between configurations).
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <memory>
#include <string>
#include <vector>

#include "verilated.h"
#if VM_TRACE
#include "verilated_fst_c.h"
#endif
#include "mapm_ports.h"
#if __has_include("mapm_config.h")
#include "mapm_config.h"  // the generator's parameters (mapm.top.Mapm.configHeader), when emitted with them
#endif
#include "accum.h"
#include "dram.h"
#include "expected.h"
#include "output.h"

namespace {

struct Options {
  std::string image, expected, out = ".", wave;
  uint64_t latency = 100, latencyMax = 0, maxCycles = 0, idleCycles = 200000, seed = 1, waveStart = 0, waveEnd = UINT64_MAX;
  double bandwidth = 14.0, clockGhz = 1.5, queryGap = 0, reqStall = 0, respGap = 0;
};

[[noreturn]] void usage(const std::string& msg) {
  fprintf(stderr,
          "mapm-harness: %s\nusage: harness --image FILE --expected FILE [--out DIR] [--latency N] [--latency-max N] [--bandwidth B]\n"
          "  [--query-gap P] [--req-stall P] [--resp-gap P] [--max-cycles N] [--idle-cycles N] [--seed N] [--clock-ghz F]\n"
          "  [--wave FILE.fst --wave-start N --wave-end N]\n",
          msg.c_str());
  exit(2);
}

Options parse(int argc, char** argv) {
  Options o;
  for (int i = 1; i < argc; i++) {
    std::string a = argv[i];
    if (a.rfind("+verilator", 0) == 0) continue;
    if (i + 1 >= argc) usage("option " + a + " needs a value");
    std::string v = argv[++i];
    char* end = nullptr;
    auto u = [&]() { uint64_t r = strtoull(v.c_str(), &end, 10); if (*end || v.empty()) usage(a + ": not a number: " + v); return r; };
    auto d = [&]() { double r = strtod(v.c_str(), &end); if (*end || v.empty() || !(r > 0)) usage(a + ": not a positive number: " + v); return r; };
    auto prob = [&]() { double r = strtod(v.c_str(), &end); if (*end || v.empty() || !(r >= 0 && r < 1)) usage(a + ": not a probability in [0, 1): " + v); return r; };
    if (a == "--image") o.image = v;
    else if (a == "--expected") o.expected = v;
    else if (a == "--out") o.out = v;
    else if (a == "--latency") o.latency = u();
    else if (a == "--latency-max") o.latencyMax = u();
    else if (a == "--bandwidth") o.bandwidth = d();
    else if (a == "--query-gap") o.queryGap = prob();
    else if (a == "--req-stall") o.reqStall = prob();
    else if (a == "--resp-gap") o.respGap = prob();
    else if (a == "--max-cycles") o.maxCycles = u();
    else if (a == "--idle-cycles") o.idleCycles = u();
    else if (a == "--seed") o.seed = u();
    else if (a == "--clock-ghz") o.clockGhz = d();
    else if (a == "--wave") o.wave = v;
    else if (a == "--wave-start") o.waveStart = u();
    else if (a == "--wave-end") o.waveEnd = u();
    else usage("unknown option " + a);
  }
  if (o.image.empty() || o.expected.empty()) usage("--image and --expected are required");
  if (o.latencyMax && o.latencyMax < o.latency) usage("--latency-max must be at least --latency");
  return o;
}

template <typename T> T le(const std::vector<uint8_t>& b, uint64_t at) { T v; memcpy(&v, &b[at], sizeof(T)); return v; }

// The fields of the memory image header (docs/memory-layout.md) the harness needs.
struct Image {
  std::vector<uint8_t> bytes;
  int ew = 0, mw = 0, slot = 4;
  uint32_t nodes = 0, queries = 0, streamEntries = 0, h = 0;
  uint64_t photonBase = 0, queryBase = 0, streamBase = 0;

  std::string load(const std::string& path) {
    FILE* f = fopen(path.c_str(), "rb");
    if (!f) return path + ": cannot open";
    fseek(f, 0, SEEK_END);
    long n = ftell(f);
    fseek(f, 0, SEEK_SET);
    bytes.resize(n < 0 ? 0 : n);
    size_t got = fread(bytes.data(), 1, bytes.size(), f);
    fclose(f);
    if (got != bytes.size() || bytes.size() < 64 || memcmp(bytes.data(), "MAPMIMG1", 8) != 0) return path + ": not a MAPM memory image";
    ew = bytes[10]; mw = bytes[11]; slot = bytes[13];
    nodes = le<uint32_t>(bytes, 16); queries = le<uint32_t>(bytes, 20); streamEntries = le<uint32_t>(bytes, 24);
    h = le<uint32_t>(bytes, 28);
    photonBase = le<uint64_t>(bytes, 32); queryBase = le<uint64_t>(bytes, 40); streamBase = le<uint64_t>(bytes, 48);
    if (le<uint64_t>(bytes, 56) != bytes.size()) return path + ": size differs from its header";
    return "";
  }
  uint64_t slotAt(uint64_t at) const { return slot == 4 ? le<uint32_t>(bytes, at) : le<uint16_t>(bytes, at); }
  uint32_t pixel(uint32_t q) const { return le<uint32_t>(bytes, queryBase + (slot == 4 ? 32 : 16) * (uint64_t)q + (slot == 4 ? 28 : 12)); }
  uint64_t streamField(uint32_t k, int f) const { return slotAt(streamBase + 16ull * k + f * slot); }
  uint32_t streamQuery(uint32_t k) const { return le<uint32_t>(bytes, streamBase + 16ull * k + 12); }
};

std::string hexs(uint64_t v) { char b[24]; snprintf(b, sizeof b, "0x%llx", (unsigned long long)v); return b; }

std::string describe(const OutBeat& o) {
  return "colour " + hexs(o.colour[0]) + " " + hexs(o.colour[1]) + " " + hexs(o.colour[2]) + ", flags " +
         std::to_string(o.flags[0]) + " " + std::to_string(o.flags[1]) + " " + std::to_string(o.flags[2]) + ", cond " +
         std::to_string(o.cond);
}
std::string describe(const SoRecord& r) {
  return "colour " + hexs(r.colour[0]) + " " + hexs(r.colour[1]) + " " + hexs(r.colour[2]) + ", flags " +
         std::to_string(r.flags(0)) + " " + std::to_string(r.flags(1)) + " " + std::to_string(r.flags(2)) + ", cond " +
         std::to_string(r.cond());
}

}  // namespace

int main(int argc, char** argv) {
  const auto wall0 = std::chrono::steady_clock::now();
  Options opt = parse(argc, argv);
  Image img;
  Expected exp;
  std::string failure;
  auto fatal = [&](const std::string& m) { printf("FAIL seed=%llu: %s\n", (unsigned long long)opt.seed, m.c_str()); exit(1); };
  if (!(failure = img.load(opt.image)).empty()) fatal(failure);
  if (!(failure = exp.load(opt.expected, img.queries)).empty()) fatal(failure);
  if (exp.ew != img.ew || exp.mw != img.mw) fatal("the expected-SO file and the image use different formats");
  if (1 + img.ew + img.mw != FMT_WIDTH) fatal("the image's format e" + std::to_string(img.ew) + "m" + std::to_string(img.mw) +
                                              " is not the hardware's (" + std::to_string(FMT_WIDTH) + " bits)");
  const uint64_t pixels = (uint64_t)exp.width * exp.height;
  for (uint32_t q = 0; q < img.queries; q++)
    if (img.pixel(q) >= pixels) fatal("query " + std::to_string(q) + " has pixel " + std::to_string(img.pixel(q)) + " outside the image");
#if !VM_TRACE
  if (!opt.wave.empty()) fatal("--wave needs a harness built with --trace-fst");
#endif

  auto ctx = std::make_unique<VerilatedContext>();
  ctx->commandArgs(argc, argv);
  auto top = std::make_unique<Top>(ctx.get());
#if VM_TRACE
  std::unique_ptr<VerilatedFstC> fst;
  if (!opt.wave.empty()) {
    ctx->traceEverOn(true);
    fst = std::make_unique<VerilatedFstC>();
    top->trace(fst.get(), 99);
    fst->open(opt.wave.c_str());
  }
#endif
  Top* t = top.get();
  uint64_t cycle = 0;  // cycles since reset was released
  bool inReset = true;
  auto half = [&](int clk) {
    t->clock = clk;
    t->eval();
    ctx->timeInc(1);
#if VM_TRACE
    if (fst && !inReset && cycle >= opt.waveStart && cycle <= opt.waveEnd) fst->dump(ctx->time());
#endif
  };

  setConfig(t, img.h, 64, img.photonBase, img.queryBase, img.nodes);
  setQuery(t, false, 0, 0, 0, 0);
  uint8_t beat[MEM_DATA_BYTES] = {0};
  setMemResp(t, false, beat, 0, false);
  setMemReqReady(t, true);
  t->reset = 1;
  for (int i = 0; i < 10; i++) { half(0); half(1); }
  t->reset = 0;
  inReset = false;

  Dram dram(img.bytes, MEM_DATA_BYTES, opt.latency, opt.latencyMax ? opt.latencyMax : opt.latency, opt.bandwidth, opt.respGap, opt.seed);
  // Host-side randomness (query-stream gaps, request back-pressure), apart from the DRAM's.
  std::mt19937_64 host(opt.seed * 0x9e3779b97f4a7c15ull + 1);
  std::uniform_real_distribution<double> coin(0.0, 1.0);
  ExactAccumulators acc(ExactFormat(img.ew, img.mw), 3 * pixels);
  std::vector<uint8_t> queryDone(img.queries, 0);
  uint64_t fed = 0, completed = 0, soOut = 0, soPassed = 0, lastActivity = 0;
  OutBeat outs[OUT_PORTS];
  auto lastProgress = std::chrono::steady_clock::now();
  auto complete = [&](uint32_t q) { if (!queryDone[q] && exp.remaining[q] == 0) { queryDone[q] = 1; completed++; } };

  while (failure.empty()) {
    // Drive this cycle's inputs.
    const bool qValid = fed < img.streamEntries && !(opt.queryGap > 0 && coin(host) < opt.queryGap);
    const bool reqReady = !(opt.reqStall > 0 && coin(host) < opt.reqStall);
    setMemReqReady(t, reqReady);
    if (qValid) {
      const uint32_t k = (uint32_t)fed;
      setQuery(t, true, img.streamField(k, 0), img.streamField(k, 1), img.streamField(k, 2), img.streamQuery(k));
    } else setQuery(t, false, 0, 0, 0, 0);
    uint64_t rid = 0;
    bool rlast = false;
    const bool rValid = dram.present(cycle, beat, &rid, &rlast);
    setMemResp(t, rValid, beat, rid, rlast);
    half(0);
    // Sample the handshakes and outputs of this cycle.
    if (fed == img.streamEntries && doneOut(t)) {
      if (dram.outstanding()) failure = "io_done high with " + std::to_string(dram.outstanding()) + " memory requests outstanding";
      break;
    }
    const bool qFire = qValid && queryReady(t);
    const bool reqFire = reqReady && memReqValid(t);
    const uint64_t reqAddr = memReqAddr(t), reqId = memReqId(t), reqLen = memReqLen(t);
    const bool respFire = rValid && memRespReady(t);
    readOuts(t, outs);
    const bool err = errorOut(t);
    half(1);
    // Apply them.
    if (qFire) { const uint32_t q = img.streamQuery((uint32_t)fed); fed++; complete(q); }
    if (reqFire) failure = dram.request(cycle, reqAddr, reqId, reqLen);
    if (respFire) dram.taken();
    bool anyOut = false;
    for (int p = 0; p < OUT_PORTS && failure.empty(); p++) {
      const OutBeat& o = outs[p];
      if (!o.valid) continue;
      anyOut = true;
      bool dup = false;
      const int64_t i = exp.take(o.q, o.photon, &dup);
      auto so = [&] {
        return "SO (q=" + std::to_string(o.q) + ", photon=" + std::to_string(o.photon) + ") on port " + std::to_string(p) +
               " at cycle " + std::to_string(cycle);
      };
      if (i < 0) { failure = (dup ? "duplicate " : "unexpected ") + so() + ": " + describe(o); break; }
      const SoRecord& r = exp.rec[i];
      bool same = o.cond == r.cond();
      for (int c = 0; c < 3; c++) same = same && o.colour[c] == r.colour[c] && o.flags[c] == (uint32_t)r.flags(c);
      if (!same) { failure = "mismatch " + so() + ": got " + describe(o) + "; expected " + describe(r); break; }
      soOut++;
      if (o.cond) {
        soPassed++;
        const uint64_t px = img.pixel(o.q);
        for (int c = 0; c < 3; c++) acc.add(3 * px + c, o.colour[c]);
      }
      complete((uint32_t)o.q);
    }
    if (qFire || reqFire || respFire || anyOut) lastActivity = cycle;
    if (failure.empty() && err) failure = "io_error raised at cycle " + std::to_string(cycle);
    cycle++;
    if (failure.empty() && opt.maxCycles && cycle >= opt.maxCycles)
      failure = "watchdog: --max-cycles " + std::to_string(opt.maxCycles) + " reached";
    if (failure.empty() && cycle - lastActivity > opt.idleCycles)
      failure = "watchdog: no handshake or result for " + std::to_string(opt.idleCycles) + " cycles";
    if ((cycle & 4095) == 0) {
      auto now = std::chrono::steady_clock::now();
      if (now - lastProgress > std::chrono::milliseconds(500)) {
        lastProgress = now;
        fprintf(stderr, "progress %llu %u %llu\n", (unsigned long long)completed, img.queries, (unsigned long long)cycle);
        fflush(stderr);
      }
    }
  }
  fprintf(stderr, "progress %llu %u %llu\n", (unsigned long long)completed, img.queries, (unsigned long long)cycle);
  if (failure.empty() && fed < img.streamEntries) failure = "done before every query was fed";
  if (failure.empty()) {
    uint64_t missing = 0, firstMissing = 0;
    for (uint64_t i = exp.rec.size(); i-- > 0;)
      if (!exp.seen[i]) { missing++; firstMissing = i; }
    if (missing)
      failure = std::to_string(missing) + " expected SOs never came out (first: q=" + std::to_string(exp.rec[firstMissing].q) +
                ", photon=" + std::to_string(exp.rec[firstMissing].photon) + ")";
  }
#if VM_TRACE
  if (fst) fst->close();
#endif
  top->final();

  // Frame and stats.
  std::vector<double> rgb(3 * pixels);
  for (uint64_t i = 0; i < rgb.size(); i++) rgb[i] = acc.toDouble(i);
  const std::string out = opt.out + "/";
  if (!writePfm(out + "frame.pfm", rgb, exp.width, exp.height) || !writeDoubles(out + "frame.f64", rgb))
    fatal("cannot write the frame into " + opt.out);
  const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - wall0).count();
  uint64_t counters[COUNTER_COUNT + 1];
  readCounters(t, counters);
  auto counter = [&](const std::string& n, uint64_t* v) {
    for (int i = 0; i < COUNTER_COUNT; i++) if (n == COUNTER_NAMES[i]) { *v = counters[i]; return true; }
    return false;
  };
  const double cyc = cycle ? (double)cycle : 1.0;
  Json j;
  j.begin();
  j.str("top", MAPM_TOP_NAME);
#ifdef MAPM_NAME
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
#endif
  j.str("result", failure.empty() ? "PASS" : "FAIL");
  if (failure.empty()) j.null("failure"); else j.str("failure", failure);
  j.integer("seed", opt.seed);
  j.integer("latency", opt.latency);
  j.integer("latencyMax", opt.latencyMax ? opt.latencyMax : opt.latency);
  j.num("queryGap", opt.queryGap);
  j.num("reqStall", opt.reqStall);
  j.num("respGap", opt.respGap);
  j.num("bandwidthBytesPerCycle", opt.bandwidth);
  j.num("clockGHz", opt.clockGhz);
  j.integer("cycles", cycle);
  j.integer("queries", fed);
  j.integer("queriesCompleted", completed);
  j.integer("soIssued", soOut);
  j.integer("soPassingCond", soPassed);
  j.num("soPerCycle", soOut / cyc);
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
  j.num("wallSeconds", wall);
  j.num("simulatedCyclesPerSecond", cycle / (wall > 0 ? wall : 1e-9));
  j.end();
  FILE* sf = fopen((out + "stats.json").c_str(), "w");
  if (!sf) fatal("cannot write " + out + "stats.json");
  fputs(j.text().c_str(), sf);
  fclose(sf);
  if (!failure.empty()) fatal(failure);
  printf("PASS seed=%llu\n", (unsigned long long)opt.seed);
  return 0;
}
