// The harness's command line (docs/harness.md), parsed with getopt_long. Arguments starting with
// `+verilator` are left to Verilator.
#pragma once
#include <getopt.h>

#include <algorithm>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string>

#include "fault.h"

struct Options {
  std::string image, expected, out = ".", wave, results;
  uint64_t latency = 100, latencyMax = 0, maxCycles = 0, idleCycles = 200000, seed = 1, waveStart = 0, waveEnd = UINT64_MAX;
  double bandwidth = 14.0, clockGhz = 1.5, queryGap = 0, reqStall = 0, respGap = 0, tailProb = 0;
  uint64_t tailLatency = 0, faultAt = 0;
  uint64_t measureFrom = UINT64_MAX;  // --measure-from: callgrind counts from this cycle to the end of the run
  int64_t frameScale = -40;           // --frame-scale: FRAME_SCALE of the coprocessor's pass (docs/coprocessor.md)
  bool poll = false;                  // --poll: the coprocessor's driver polls STATUS instead of waiting for the interrupt
  bool readStream = false;            // --read-stream: the coprocessor reads the query stream even where it is the identity
  std::string badConfig;              // --bad-config KIND: the coprocessor's pass configured wrong on purpose (coproc.cpp)
  Fault fault = Fault::None;
};

[[noreturn]] inline void usage(const std::string& msg) {
  fprintf(stderr,
          "mapm-harness: %s\nusage: harness --image FILE --expected FILE [--out DIR] [--latency N] [--latency-max N] [--bandwidth B]\n"
          "  [--query-gap P] [--req-stall P] [--resp-gap P] [--tail-prob P --tail-latency N] [--max-cycles N] [--idle-cycles N]\n"
          "  [--seed N] [--clock-ghz F] [--fault KIND [--fault-at N]] (fault.h)\n"
          "  [--wave FILE.fst --wave-start N --wave-end N] [--results FILE] [--measure-from N] [--frame-scale S] [--poll] [--read-stream]\n",
          msg.c_str());
  exit(2);
}

inline Options parseOptions(int argc, char** argv) {
  enum { IMAGE = 1, EXPECTED, OUT, LATENCY, LATENCY_MAX, BANDWIDTH, QUERY_GAP, REQ_STALL, RESP_GAP, MAX_CYCLES, IDLE_CYCLES,
         SEED, CLOCK_GHZ, WAVE, WAVE_START, WAVE_END, TAIL_PROB, TAIL_LATENCY, FAULT, FAULT_AT, RESULTS, MEASURE_FROM,
         FRAME_SCALE, POLL, BAD_CONFIG, READ_STREAM };
  static const option longOptions[] = {
      {"image", required_argument, nullptr, IMAGE},           {"expected", required_argument, nullptr, EXPECTED},
      {"out", required_argument, nullptr, OUT},               {"latency", required_argument, nullptr, LATENCY},
      {"latency-max", required_argument, nullptr, LATENCY_MAX}, {"bandwidth", required_argument, nullptr, BANDWIDTH},
      {"query-gap", required_argument, nullptr, QUERY_GAP},   {"req-stall", required_argument, nullptr, REQ_STALL},
      {"resp-gap", required_argument, nullptr, RESP_GAP},     {"max-cycles", required_argument, nullptr, MAX_CYCLES},
      {"idle-cycles", required_argument, nullptr, IDLE_CYCLES}, {"seed", required_argument, nullptr, SEED},
      {"clock-ghz", required_argument, nullptr, CLOCK_GHZ},   {"wave", required_argument, nullptr, WAVE},
      {"wave-start", required_argument, nullptr, WAVE_START}, {"wave-end", required_argument, nullptr, WAVE_END},
      {"tail-prob", required_argument, nullptr, TAIL_PROB},   {"tail-latency", required_argument, nullptr, TAIL_LATENCY},
      {"fault", required_argument, nullptr, FAULT},           {"fault-at", required_argument, nullptr, FAULT_AT},
      {"results", required_argument, nullptr, RESULTS},       {"measure-from", required_argument, nullptr, MEASURE_FROM},
      {"frame-scale", required_argument, nullptr, FRAME_SCALE}, {"poll", no_argument, nullptr, POLL},
      {"bad-config", required_argument, nullptr, BAD_CONFIG}, {"read-stream", no_argument, nullptr, READ_STREAM},
      {nullptr, 0, nullptr, 0}};
  Options o;
  opterr = 0;  // the errors below say what went wrong
  int c, index = -1;
  while ((c = getopt_long(argc, argv, ":", longOptions, &index)) != -1) {
    const std::string a = argv[optind - 1];
    if (c == ':') usage("option " + a + " needs a value");
    if (c == '?') usage("unknown option " + a);
    const std::string name = std::string("--") + longOptions[index].name, v = optarg ? optarg : "";
    char* end = nullptr;
    auto u = [&]() { uint64_t r = strtoull(v.c_str(), &end, 10); if (*end || v.empty()) usage(name + ": not a number: " + v); return r; };
    auto d = [&]() { double r = strtod(v.c_str(), &end); if (*end || v.empty() || !(r > 0)) usage(name + ": not a positive number: " + v); return r; };
    auto prob = [&]() { double r = strtod(v.c_str(), &end); if (*end || v.empty() || !(r >= 0 && r < 1)) usage(name + ": not a probability in [0, 1): " + v); return r; };
    switch (c) {
      case IMAGE: o.image = v; break;
      case EXPECTED: o.expected = v; break;
      case OUT: o.out = v; break;
      case LATENCY: o.latency = u(); break;
      case LATENCY_MAX: o.latencyMax = u(); break;
      case BANDWIDTH: o.bandwidth = d(); break;
      case QUERY_GAP: o.queryGap = prob(); break;
      case REQ_STALL: o.reqStall = prob(); break;
      case RESP_GAP: o.respGap = prob(); break;
      case MAX_CYCLES: o.maxCycles = u(); break;
      case IDLE_CYCLES: o.idleCycles = u(); break;
      case SEED: o.seed = u(); break;
      case CLOCK_GHZ: o.clockGhz = d(); break;
      case WAVE: o.wave = v; break;
      case WAVE_START: o.waveStart = u(); break;
      case WAVE_END: o.waveEnd = u(); break;
      case TAIL_PROB: o.tailProb = prob(); break;
      case TAIL_LATENCY: o.tailLatency = u(); break;
      case FAULT: if (!parseFault(v, &o.fault)) usage("--fault: unknown fault " + v); break;
      case FAULT_AT: o.faultAt = u(); break;
      case RESULTS: o.results = v; break;
      case MEASURE_FROM: o.measureFrom = u(); break;
      case FRAME_SCALE: { long long r = strtoll(v.c_str(), &end, 10); if (*end || v.empty() || r < -32768 || r > 32767) usage(name + ": not a scale in -32768..32767: " + v); o.frameScale = r; break; }
      case POLL: o.poll = true; break;
      case READ_STREAM: o.readStream = true; break;
      case BAD_CONFIG: o.badConfig = v; break;
    }
  }
  for (int i = optind; i < argc; i++)  // getopt_long moves the arguments that are not options here
    if (std::string(argv[i]).rfind("+verilator", 0) != 0) usage("unknown option " + std::string(argv[i]));
  if (o.image.empty() || o.expected.empty()) usage("--image and --expected are required");
  if (o.latencyMax && o.latencyMax < o.latency) usage("--latency-max must be at least --latency");
  if (o.tailProb > 0 && o.tailLatency < std::max(o.latency, o.latencyMax)) usage("--tail-latency must be at least --latency-max");
  return o;
}
