// Verilator harness for the MAPM coprocessor (docs/harness.md, docs/coprocessor.md). It plays the
// CPU and the DRAM: the memory holds the image and a frame buffer after it; the C driver
// (tools/driver) configures a frame pass over AXI4-Lite, starts it and waits for the interrupt (or
// polls with --poll); the coprocessor reads its stream and records and writes the frame buffer over
// AXI4. Every SO on the trace ports is checked against the expected SOs, and the frame is read
// back from the frame buffer. Ends with one line: `PASS seed=N` or `FAIL seed=N: reason`.
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <random>
#include <string>
#include <vector>

#include "verilated.h"
#include "axiwrite.h"
#include "check.h"
#include "dram.h"
#include "expected.h"
#include "fault.h"
#include "image.h"
#include "mapm_config.h"
#include "options.h"
#include "output.h"
#include "stats.h"
#include "wave.h"
extern "C" {
#include "mapm_driver.h"
}
#include "mapm_driver.c"
#include "mapm_run_frame.c"  // docs/examples: the driver's example, which runs every pass here

namespace {

// The simulated system: the coprocessor, its memory and the register port's master side.
struct System {
  const Options& opt;
  std::unique_ptr<VerilatedContext> ctx;
  std::unique_ptr<Top> top;
  std::unique_ptr<Waveform<Top>> wave;
  bool inReset = true;
  Dram& dram;
  WriteSlave& wr;
  Checker& check;
  ResponseFault& fault;
  std::mt19937_64 host;
  std::uniform_real_distribution<double> coin{0.0, 1.0};
  uint64_t cycle = 0, lastActivity = 0;
  std::string failure;
  uint8_t beat[MAPM_MEM_DATA_BYTES] = {0};
  // The register port's pending access, set by the driver's callbacks.
  bool awV = false, wV = false, arV = false, bR = false, rR = false;
  uint32_t ctrlAddr = 0, ctrlData = 0;
  bool awDone = false, wDone = false, arDone = false, bDone = false, rDone = false;
  uint32_t rData = 0;
  unsigned ctrlResp = 0;

  System(const Options& o, int argc, char** argv, Dram& d, WriteSlave& w, Checker& c, ResponseFault& f)
      : opt(o), ctx(std::make_unique<VerilatedContext>()), dram(d), wr(w), check(c), fault(f), host(o.seed * 0x9e3779b97f4a7c15ull + 1) {
    ctx->commandArgs(argc, argv);
    top = std::make_unique<Top>(ctx.get());
    wave = std::make_unique<Waveform<Top>>(ctx.get(), top.get(), o);
  }

  void half(int clk) { top->clock = clk; top->eval(); ctx->timeInc(1); wave->dump(cycle, inReset); }

  void reset() {
    Top* t = top.get();
    setR(t, false, beat, 0, false, 0); setB(t, false, 0, 0);
    setCtrlAw(t, false, 0); setCtrlW(t, false, 0, 0); setCtrlAr(t, false, 0);
    setCtrlBReady(t, false); setCtrlRReady(t, false);
    t->reset = 1;
    for (int i = 0; i < 10; i++) { half(0); half(1); }
    t->reset = 0;
    inReset = false;
  }

  // One clock cycle: the memory's and the register master's inputs, the outputs sampled, the edge.
  void tick() {
    Top* t = top.get();
    const bool arR = !(opt.reqStall > 0 && coin(host) < opt.reqStall);
    const bool awR = !(opt.reqStall > 0 && coin(host) < opt.reqStall);
    const bool wRdy = wr.canTake() && !(opt.reqStall > 0 && coin(host) < opt.reqStall);
    setArReady(t, arR); setAwReady(t, awR); setWReady(t, wRdy);
    uint64_t rid = 0; bool rlast = false; unsigned rresp = 0;
    bool rv = dram.present(cycle, beat, &rid, &rlast);
    const bool faultBeat = fault.inject(cycle, dram, beat, MAPM_MEM_DATA_BYTES, &rid, &rlast);  // --fault: a beat not the DRAM's
    rv = rv || faultBeat;
    if (!faultBeat) fault.alterRead(cycle, rv, &rlast, &rresp);
    setR(t, rv, beat, rid, rlast, rresp);
    uint64_t bid = 0; unsigned bresp = 0;
    bool bv = wr.response(cycle, &bid);
    const bool faultB = fault.alterWrite(cycle, bv, wr.idle(), dram.outstanding() > 0, &bv, &bid, &bresp);
    setB(t, bv, bid, bresp);
    setCtrlAw(t, awV && !awDone, ctrlAddr); setCtrlW(t, wV && !wDone, ctrlData, 0xf);
    setCtrlAr(t, arV && !arDone, ctrlAddr); setCtrlBReady(t, bR); setCtrlRReady(t, rR);
    half(0);
    const bool arFire = arR && arValid(t), rFire = rv && rReady(t);
    const bool awFire = awR && awValid(t), wFire = wRdy && wValid(t), bFire = bv && bReady(t);
    const bool cAw = awV && !awDone && ctrlAwReady(t), cW = wV && !wDone && ctrlWReady(t), cAr = arV && !arDone && ctrlArReady(t);
    const bool cB = bR && ctrlBValid(t), cR = rR && ctrlRValid(t);
    if (cB) ctrlResp = ctrlBResp(t);
    if (cR) { rData = ctrlRData(t); ctrlResp = ctrlRResp(t); }
    uint8_t wbeat[MAPM_MEM_DATA_BYTES];
    if (wFire) wData(t, wbeat);
    const uint64_t aA = arAddr(t), aI = arId(t), aL = arLen(t);
    const uint64_t wA = awAddr(t), wI = awId(t), wL = awLen(t), ws = wStrb(t);
    const bool wl = wLast(t);
    OutBeat outs[MAPM_OUT_PORTS];
    readOuts(t, outs);
    half(1);
    if (arFire && failure.empty()) failure = dram.request(cycle, aA, aI, aL);
    if (rFire && !faultBeat) dram.taken();
    if (awFire && failure.empty()) failure = wr.address(wA, wI, wL);
    if (wFire && failure.empty()) failure = wr.beat(wbeat, ws, wl, cycle);
    if (bFire && !faultB) wr.responseTaken();
    awDone = awDone || cAw; wDone = wDone || cW; arDone = arDone || cAr; bDone = bDone || cB; rDone = rDone || cR;
    bool any = arFire || rFire || awFire || wFire || bFire || cAw || cW || cAr || cB || cR;
    for (int p = 0; p < MAPM_OUT_PORTS && failure.empty(); p++)
      if (outs[p].valid) { any = true; failure = check.beat(outs[p], p, cycle); }
    if (any) lastActivity = cycle;
    cycle++;
    if (failure.empty() && cycle - lastActivity > opt.idleCycles)
      failure = "watchdog: no handshake or result for " + std::to_string(opt.idleCycles) + " cycles";
    if (failure.empty() && opt.maxCycles && cycle >= opt.maxCycles) failure = "stopped at --max-cycles " + std::to_string(opt.maxCycles);
    if (!failure.empty()) throw failure;
  }

  void write32(uint32_t off, uint32_t v) {
    ctrlAddr = off; ctrlData = v; awV = wV = true; awDone = wDone = bDone = false;
    while (!(awDone && wDone)) tick();
    awV = wV = false; bR = true;
    while (!bDone) tick();
    bR = false;
    if (ctrlResp != 0) { failure = "the register write at 0x" + hexs(off) + " answered " + std::to_string(ctrlResp); throw failure; }
  }
  uint32_t read32(uint32_t off) {
    ctrlAddr = off; arV = true; arDone = rDone = false;
    while (!arDone) tick();
    arV = false; rR = true;
    while (!rDone) tick();
    rR = false;
    if (ctrlResp != 0) { failure = "the register read at 0x" + hexs(off) + " answered " + std::to_string(ctrlResp); throw failure; }
    return rData;
  }
  int waitIrq() {
    while (!irqOut(top.get())) tick();
    return 1;
  }
  static std::string hexs(uint64_t v) { char b[24]; snprintf(b, sizeof b, "%llx", (unsigned long long)v); return b; }
};

System* sys = nullptr;
uint32_t busRead(void*, uint32_t off) { return sys->read32(off); }
void busWrite(void*, uint32_t off, uint32_t v) { sys->write32(off, v); }
int busWaitIrq(void*) { return sys->waitIrq(); }

double decode(uint64_t bits, int ew, int mw) {
  const uint64_t e = (bits >> mw) & ((1ull << ew) - 1), m = bits & ((1ull << mw) - 1);
  const bool neg = (bits >> (ew + mw)) & 1;
  double v;
  if (e == 0) v = 0.0;
  else if (e == (1ull << ew) - 1) v = m ? std::nan("") : INFINITY;
  else v = std::ldexp((double)((1ull << mw) | m), (int)e - ((1 << (ew - 1)) - 1) - mw);
  return neg ? -v : v;
}

}  // namespace

int main(int argc, char** argv) {
  const auto wall0 = std::chrono::steady_clock::now();
  const Options opt = parseOptions(argc, argv);
  Image img;
  Expected exp;
  std::string failure;
  auto fatal = [&](const std::string& m) { printf("FAIL seed=%llu: %s\n", (unsigned long long)opt.seed, m.c_str()); exit(1); };
  if (!(failure = img.load(opt.image, MAPM_EXP_WIDTH, MAPM_MAN_WIDTH, MAPM_SLOT_BYTES)).empty()) fatal(failure);
  if (!(failure = exp.load(opt.expected, img.queries)).empty()) fatal(failure);
  if (!(failure = corruptImage(opt.fault, img)).empty()) fatal(failure);
  if (opt.fault == Fault::QueryIndex)  // stream entry 0 names no query
    for (int i = 0; i < 4; i++) img.bytes[img.streamBase + i] = (uint8_t)((img.queries + 1000u) >> (8 * i));
  const uint64_t pixels = (uint64_t)exp.width * exp.height;
#if !VM_TRACE
  if (!opt.wave.empty()) fatal("--wave needs a harness built with --trace-fst");
#endif
  if (pixels > (1ull << MAPM_TILE_LOG2)) fatal("the frame's " + std::to_string(pixels) + " pixels exceed the coprocessor's pass of 2^" + std::to_string(MAPM_TILE_LOG2));

  // The memory: the image, then the frame buffer at the next 4 KiB boundary (filled with 0xa5 so
  // that a byte the coprocessor never wrote shows).
  std::vector<uint8_t> mem = img.bytes;
  const uint64_t frameBase = (mem.size() + 4095) / 4096 * 4096;
  const uint64_t frameEnd = frameBase + pixels * MAPM_PIXEL_BYTES;
  mem.resize(frameEnd, 0xa5);
  std::vector<std::pair<uint64_t, uint64_t>> readable = img.readable();
  readable.push_back({img.streamBase, img.bytes.size()});
  Dram dram(mem, readable, MAPM_MEM_DATA_BYTES, opt.latency, opt.latencyMax ? opt.latencyMax : opt.latency, opt.bandwidth, opt.respGap,
            opt.seed, opt.tailProb, opt.tailLatency);
  WriteSlave wr(mem, frameBase, frameEnd, MAPM_MEM_DATA_BYTES, opt.latency, opt.bandwidth);
  Checker check(exp, img, pixels);
  ResponseFault fault(opt.fault, opt.faultAt, MAPM_MEM_ID_BITS);
  System s(opt, argc, argv, dram, wr, check, fault);
  sys = &s;
  s.reset();
  mapm_bus bus = {busRead, busWrite, opt.poll ? nullptr : busWaitIrq, nullptr};
  uint64_t counters[COUNTER_COUNT + 1] = {0};
  uint64_t passCycles = 0;
  bool stopped = false;
  try {
    mapm_frame f = {};
    f.exp_width = img.ew; f.man_width = img.mw; f.slot_bytes = img.slot;
    f.node_base = IMAGE_BYTES; f.photon_base = img.photonBase; f.query_base = img.queryBase; f.stream_base = img.streamBase;
    f.frame_base = frameBase; f.radius = img.h; f.node_count = img.nodes; f.query_count = img.queries;
    f.pixel_base = 0; f.pixel_count = (uint32_t)pixels; f.frame_scale = (int32_t)opt.frameScale;
    // The records in the order to run them need no stream; --read-stream reads it all the same.
    bool identity = true;
    for (uint32_t k = 0; k < img.queries && identity; k++) identity = img.streamQuery(k) == k;
    f.use_stream = opt.readStream || !identity;
    static_assert(MAPM_COUNTER_COUNT == COUNTER_COUNT, "the register map's counters are the top's");
    // --bad-config: one thing wrong, which the driver or the pass's check must refuse with its reason.
    const std::string& bad = opt.badConfig;
    if (bad == "misaligned") f.photon_base += 16;
    else if (bad == "overlap") f.frame_base = f.query_base;
    else if (bad == "no-queries") f.query_count = 0;
    else if (bad == "too-many-pixels") f.pixel_count = (1u << MAPM_TILE_LOG2) + 1;
    else if (bad == "format") f.man_width += 1;
    else if (!bad.empty()) fatal("--bad-config: one of misaligned, overlap, no-queries, too-many-pixels, format; got " + bad);
    const uint64_t started = s.cycle;
    char why[512];
    const int rc = mapm_run_frame(&bus, &f, !opt.poll, counters, why, sizeof why);
    passCycles = s.cycle - started;
    if (rc != MAPM_OK) failure = std::string("driver: ") + why;
  } catch (const std::string& why) {
    failure = why;
    stopped = why.rfind("stopped at --max-cycles", 0) == 0;
    if (stopped) failure.clear();
  }
  if (failure.empty() && !stopped) failure = check.missing();
  if (failure.empty() && !stopped && opt.fault != Fault::None) failure = "the injected fault was not flagged";
  if (!failure.empty() && opt.fault != Fault::None)
    failure += std::string(" (injected fault: ") + faultName(opt.fault) +
               (fault.injected() ? " at cycle " + std::to_string(fault.cycle()) : std::string()) + ")";
  if (failure.empty() && !stopped && !wr.idle()) failure = "a write was still unanswered at the end of the pass";
  if (failure.empty() && !stopped && dram.outstanding()) failure = std::to_string(dram.outstanding()) + " reads outstanding at the end of the pass";
  s.wave->close();
  s.top->final();

  // The frame: from the frame buffer (full fidelity); the SOAs' timing model computes no colour.
  const std::string out = opt.out + "/";
  if (!MAPM_FIDELITY_TIMING && !stopped) {
    std::vector<double> rgb(3 * pixels);
    for (uint64_t i = 0; i < pixels && failure.empty(); i++)
      for (int c = 0; c < 3; c++) {
        uint64_t bits = 0;
        memcpy(&bits, &mem[frameBase + i * MAPM_PIXEL_BYTES + c * MAPM_SLOT_BYTES], MAPM_SLOT_BYTES);
        rgb[3 * i + c] = decode(bits & (MAPM_FORMAT_WIDTH == 64 ? ~0ull : (1ull << MAPM_FORMAT_WIDTH) - 1), MAPM_EXP_WIDTH, MAPM_MAN_WIDTH);
        if (MAPM_FORMAT_WIDTH < 8 * MAPM_SLOT_BYTES && (bits >> MAPM_FORMAT_WIDTH) != 0)
          failure = "pixel " + std::to_string(i) + " channel " + std::to_string(c) + ": bits above the format in its slot (a byte not written?)";
      }
    if (!writePfm(out + "frame.pfm", rgb, exp.width, exp.height) || !writeDoubles(out + "frame.f64", rgb))
      fatal("cannot write the frame into " + opt.out);
  }
  const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - wall0).count();
  check.completeAll();
  const RunSummary run{failure, stopped, s.cycle, counters[1], check.completed, check.soOut, check.soPassed, wall};
  if (!writeStats(out + "stats.json", opt, run, dram, counters, passCycles, wr.bytesWritten())) fatal("cannot write " + out + "stats.json");
  if (!failure.empty()) fatal(failure);
  if (stopped) {
    printf("STOPPED at cycle %llu as asked (--max-cycles %llu): %llu results out, each checked; the rest not run\n",
           (unsigned long long)s.cycle, (unsigned long long)opt.maxCycles, (unsigned long long)check.soOut);
    return 0;
  }
  printf("PASS seed=%llu%s\n", (unsigned long long)opt.seed,
         MAPM_FIDELITY_TIMING ? " (timing model: (q, photon), counts and cycles checked; colours from the model)" : "");
  return 0;
}
