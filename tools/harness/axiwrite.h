// The write side of the coprocessor's memory (docs/harness.md): takes AXI4 write bursts (AW, then
// its W beats), writes the strobed bytes into the memory, and answers each burst with one B after
// the memory latency. Every burst must lie inside the writable span (the frame buffer). Writes take
// the memory's bandwidth as reads do (--bandwidth bytes per cycle; the frame is written after the
// reads are done, so the two do not compete).
#pragma once
#include <cstdint>
#include <cstring>
#include <deque>
#include <string>
#include <vector>

class WriteSlave {
 public:
  WriteSlave(std::vector<uint8_t>& mem, uint64_t lo, uint64_t hi, int dataBytes, uint64_t latency, double bytesPerCycle)
      : mem_(mem), lo_(lo), hi_(hi), dataBytes_(dataBytes), latency_(latency), bandwidth_(bytesPerCycle) {}

  // Whether a W beat can be taken this cycle (the bandwidth's credit), called once a cycle.
  bool canTake() {
    credit_ += bandwidth_;
    if (credit_ > dataBytes_ + bandwidth_) credit_ = dataBytes_ + bandwidth_;
    return credit_ >= dataBytes_;
  }

  // An AW taken: a burst of len + 1 beats from addr under id.
  std::string address(uint64_t addr, uint64_t id, uint64_t len) {
    const uint64_t bytes = (len + 1) * dataBytes_;
    if (addr % dataBytes_ != 0) return "memory protocol: write burst at 0x" + hex(addr) + " not aligned to a beat";
    if (addr < lo_ || addr + bytes > hi_)
      return "memory protocol: a write of " + std::to_string(bytes) + " bytes at 0x" + hex(addr) + " is outside the frame buffer";
    bursts_.push_back({addr, id, (uint32_t)(len + 1), 0});
    return "";
  }
  // A W beat taken.
  std::string beat(const uint8_t* data, uint64_t strb, bool last, uint64_t cycle) {
    if (bursts_.empty()) return "memory protocol: a W beat with no write burst";
    Burst& b = bursts_.front();
    const uint64_t at = b.addr + (uint64_t)b.sent * dataBytes_;
    for (int j = 0; j < dataBytes_; j++)
      if (strb >> j & 1) { mem_[at + j] = data[j]; bytesWritten_++; }
    b.sent++;
    credit_ -= dataBytes_;
    if (last != (b.sent == b.beats)) return "memory protocol: WLAST on beat " + std::to_string(b.sent) + " of " + std::to_string(b.beats);
    if (b.sent == b.beats) { answers_.push_back({b.id, cycle + latency_}); bursts_.pop_front(); writes_++; }
    return "";
  }
  // The B on offer this cycle, if any.
  bool response(uint64_t cycle, uint64_t* id) const {
    if (answers_.empty() || answers_.front().at > cycle) return false;
    *id = answers_.front().id;
    return true;
  }
  void responseTaken() { answers_.pop_front(); }
  bool idle() const { return bursts_.empty() && answers_.empty(); }
  uint64_t bytesWritten() const { return bytesWritten_; }
  uint64_t writes() const { return writes_; }

 private:
  struct Burst { uint64_t addr, id; uint32_t beats, sent; };
  struct Answer { uint64_t id, at; };
  static std::string hex(uint64_t v) { char s[32]; snprintf(s, sizeof s, "%llx", (unsigned long long)v); return s; }
  std::vector<uint8_t>& mem_;
  uint64_t lo_, hi_;
  int dataBytes_;
  uint64_t latency_;
  double bandwidth_, credit_ = 0;
  std::deque<Burst> bursts_;
  std::deque<Answer> answers_;
  uint64_t bytesWritten_ = 0, writes_ = 0;
};
