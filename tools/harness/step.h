// One clock cycle of the Verilated top, split where the harness samples: drive() sets the cycle's
// inputs and evaluates with the clock low, the harness looks at the returned outputs, and rise()
// clocks. The port accessors and the top's class come from the generated mapm_config.h.
#pragma once
#include <cstdint>
#include <memory>
#include <string>

#include "verilated.h"
#include "image.h"
#include "mapm_config.h"
#include "options.h"
#include "wave.h"

// The inputs of one cycle.
struct Drive {
  bool queryValid = false;
  uint64_t q = 0;
  bool reqReady = true;
  bool respValid = false;
  const uint8_t* respData = nullptr;
  uint64_t respId = 0;
  bool respLast = false;
};

// The outputs of one cycle, sampled before the clock edge.
struct Sample {
  bool done, queryReady, reqValid, respReady, error;
  uint64_t reqAddr, reqId, reqLen;
  OutBeat out[MAPM_OUT_PORTS];
};

class Bench {
 public:
  // The top, with an FST waveform of cycles opt.waveStart..opt.waveEnd when opt.wave names one
  // (traced builds only; main() refuses --wave otherwise).
  Bench(int argc, char** argv, const Options& opt) : ctx_(std::make_unique<VerilatedContext>()) {
    ctx_->commandArgs(argc, argv);
    top_ = std::make_unique<Top>(ctx_.get());
    wave_ = std::make_unique<Waveform<Top>>(ctx_.get(), top_.get(), opt);
  }

  // Sets io_cfg from the image, idles the inputs and holds reset for 10 cycles.
  void reset(const Image& img) {
    Top* t = top_.get();
    setConfig(t, img.h, IMAGE_BYTES, img.photonBase, img.queryBase, img.nodes);
    setQuery(t, false, 0);
    const uint8_t zero[MAPM_MEM_DATA_BYTES] = {0};
    setMemResp(t, false, zero, 0, false);
    setMemReqReady(t, true);
    t->reset = 1;
    for (int i = 0; i < 10; i++) { half(0); half(1); }
    t->reset = 0;
    inReset_ = false;
  }

  // Drives this cycle's inputs, evaluates with the clock low and samples the outputs.
  Sample drive(const Drive& d) {
    Top* t = top_.get();
    setMemReqReady(t, d.reqReady);
    setQuery(t, d.queryValid, d.q);
    setMemResp(t, d.respValid, d.respData, d.respId, d.respLast);
    half(0);
    Sample s;
    s.done = doneOut(t);
    s.queryReady = queryReady(t);
    s.reqValid = memReqValid(t);
    s.reqAddr = memReqAddr(t); s.reqId = memReqId(t); s.reqLen = memReqLen(t);
    s.respReady = memRespReady(t);
    readOuts(t, s.out);
    s.error = errorOut(t);
    return s;
  }

  // The rising clock edge.
  void rise() { half(1); }
  // Counts the cycle just clocked (cycles count from reset's release).
  void endCycle() { cycle_++; }
  uint64_t cycle() const { return cycle_; }

  void counters(uint64_t* v) { readCounters(top_.get(), v); }

  // Closes the waveform and finishes the model.
  void finish() {
    wave_->close();
    top_->final();
  }

 private:
  void half(int clk) {
    top_->clock = clk;
    top_->eval();
    ctx_->timeInc(1);
    wave_->dump(cycle_, inReset_);
  }

  std::unique_ptr<VerilatedContext> ctx_;
  std::unique_ptr<Top> top_;
  std::unique_ptr<Waveform<Top>> wave_;
  uint64_t cycle_ = 0;
  bool inReset_ = true;
};
