// The FST waveform of a harness run (`--wave FILE`): cycles opt.waveStart to opt.waveEnd, counted
// from reset's release, of a traced build (`--trace-fst`; the harnesses refuse --wave otherwise).
#pragma once
#include <cstdint>
#include <memory>

#include "verilated.h"
#if VM_TRACE
#include "verilated_fst_c.h"
#endif
#include "options.h"

template <class Model>
class Waveform {
 public:
  Waveform(VerilatedContext* ctx, Model* top, const Options& opt) : ctx_(ctx), opt_(opt) {
#if VM_TRACE
    if (!opt.wave.empty()) {
      ctx->traceEverOn(true);
      fst_ = std::make_unique<VerilatedFstC>();
      top->trace(fst_.get(), 99);
      fst_->open(opt.wave.c_str());
    }
#else
    (void)top;
#endif
  }
  // After each evaluation: records the signals at the context's time when `cycle` is in the window.
  void dump(uint64_t cycle, bool inReset) {
#if VM_TRACE
    if (fst_ && !inReset && cycle >= opt_.waveStart && cycle <= opt_.waveEnd) fst_->dump(ctx_->time());
#else
    (void)cycle; (void)inReset;
#endif
  }
  void close() {
#if VM_TRACE
    if (fst_) fst_->close();
#endif
  }

 private:
  VerilatedContext* ctx_;
  const Options& opt_;
#if VM_TRACE
  std::unique_ptr<VerilatedFstC> fst_;
#endif
};
