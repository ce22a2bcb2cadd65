// The DRAM the harness plays on the MAPM's memory port (docs/memory-port.md).
//
// A request taken in cycle t is ready at t + L, L drawn uniformly from [latency, latencyMax] per
// request (seeded); with probability `tailProb` from [latencyMax, tailLatency] instead (a long
// tail: refresh, a busy bank, a far channel). Each cycle at most one beat leaves, chosen
// at random (seeded) among the ready requests, so responses to different ids come back in any
// order and their beats interleave; the beats of one request stay in order. Bandwidth is a token
// bucket: `bytesPerCycle` credit per cycle, a beat of `dataBytes` needs that much credit. With
// `respGap` > 0, a beat that could be offered is held back with that probability (random gaps).
// Protocol checks (each a failure message): an address not aligned to the request's size, a
// request not wholly inside one of the readable ranges (the image's node, photon and query arrays:
// never the header, the query stream or a byte beyond the image), an id reused while its request
// is still outstanding.
#pragma once
#include <cstdint>
#include <algorithm>
#include <cstring>
#include <random>
#include <string>
#include <unordered_set>
#include <utility>
#include <vector>

class Dram {
 public:
  struct Request {
    uint64_t addr, id;
    uint32_t beats, sent;
    uint64_t readyAt;
  };

  // `readable`: the [begin, end) byte ranges a request may read, each within the image.
  Dram(const std::vector<uint8_t>& image, std::vector<std::pair<uint64_t, uint64_t>> readable, int dataBytes, uint64_t latency,
       uint64_t latencyMax, double bytesPerCycle, double respGap, uint64_t seed, double tailProb = 0, uint64_t tailLatency = 0)
      : mem_(image), readable_(std::move(readable)), dataBytes_(dataBytes), latency_(latency), latencyMax_(latencyMax), bandwidth_(bytesPerCycle),
        respGap_(respGap), tailProb_(tailProb), tailLatency_(tailLatency), rng_(seed) {}

  // Accepts a request in `cycle`; returns an error message or "".
  std::string request(uint64_t cycle, uint64_t addr, uint64_t id, uint64_t len) {
    const uint64_t bytes = (len + 1) * dataBytes_;
    if (addr % bytes != 0)
      return "memory protocol: address 0x" + hex(addr) + " not aligned to the request size " + std::to_string(bytes);
    bool inside = false;
    for (const auto& r : readable_) inside = inside || (addr >= r.first && addr + bytes <= r.second && r.second <= mem_.size());
    if (!inside)
      return "memory protocol: a read of " + std::to_string(bytes) + " bytes at 0x" + hex(addr) +
             " is outside the node, photon and query arrays of the " + std::to_string(mem_.size()) + "-byte image";
    if (!ids_.insert(id).second)
      return "memory protocol: id " + std::to_string(id) + " reused while its request is outstanding";
    uint64_t lat = latencyMax_ > latency_ ? std::uniform_int_distribution<uint64_t>(latency_, latencyMax_)(rng_) : latency_;
    if (tailProb_ > 0 && std::uniform_real_distribution<double>(0.0, 1.0)(rng_) < tailProb_)
      lat = std::uniform_int_distribution<uint64_t>(latencyMax_, std::max(latencyMax_, tailLatency_))(rng_);
    pending_.push_back({addr, id, (uint32_t)(len + 1), 0, cycle + lat});
    requests_++;
    return "";
  }

  // Chooses the beat to present this cycle (call once per cycle before the clock edge).
  // Returns false when none: no ready request or not enough bandwidth credit.
  bool present(uint64_t cycle, uint8_t* data, uint64_t* id, bool* last) {
    if (!haveBeat_) {
      credit_ += bandwidth_;
      const double cap = dataBytes_ + bandwidth_;
      if (credit_ > cap) credit_ = cap;
      if (credit_ < dataBytes_) return false;
      ready_.clear();
      for (size_t i = 0; i < pending_.size(); i++)
        if (pending_[i].readyAt <= cycle) ready_.push_back(i);
      if (ready_.empty()) return false;
      if (respGap_ > 0 && std::uniform_real_distribution<double>(0.0, 1.0)(rng_) < respGap_) return false;
      chosen_ = ready_[std::uniform_int_distribution<size_t>(0, ready_.size() - 1)(rng_)];
      haveBeat_ = true;
    }
    const Request& r = pending_[chosen_];
    const uint64_t at = r.addr + (uint64_t)r.sent * dataBytes_;
    memcpy(data, &mem_[at], dataBytes_);  // inside the image: request() checked the range
    *id = r.id;
    *last = r.sent + 1 == r.beats;
    return true;
  }

  // The presented beat was taken by the hardware.
  void taken() {
    Request& r = pending_[chosen_];
    r.sent++;
    bytes_ += dataBytes_;
    credit_ -= dataBytes_;
    if (r.sent == r.beats) {
      ids_.erase(r.id);
      lastDoneId_ = r.id;
      lastDoneAddr_ = r.addr + (uint64_t)(r.beats - 1) * dataBytes_;
      anyDone_ = true;
      pending_[chosen_] = pending_.back();
      pending_.pop_back();
    }
    haveBeat_ = false;
  }

  size_t outstanding() const { return pending_.size(); }
  bool isOutstanding(uint64_t id) const { return ids_.count(id) != 0; }
  // The id and last beat of the request finished last; false before any has finished.
  bool lastDone(uint64_t* id, uint8_t* data) const {
    if (!anyDone_) return false;
    *id = lastDoneId_;
    memcpy(data, &mem_[lastDoneAddr_], dataBytes_);
    return true;
  }
  uint64_t bytesServed() const { return bytes_; }
  uint64_t requests() const { return requests_; }

 private:
  static std::string hex(uint64_t v) {
    char b[32];
    snprintf(b, sizeof b, "%llx", (unsigned long long)v);
    return b;
  }

  const std::vector<uint8_t>& mem_;
  const std::vector<std::pair<uint64_t, uint64_t>> readable_;
  int dataBytes_;
  uint64_t latency_, latencyMax_;
  double bandwidth_, respGap_, tailProb_;
  uint64_t tailLatency_;
  double credit_ = 0;
  std::mt19937_64 rng_;
  std::vector<Request> pending_;
  std::vector<size_t> ready_;
  std::unordered_set<uint64_t> ids_;
  bool haveBeat_ = false;  // a beat is presented and held until taken (stable until taken)
  size_t chosen_ = 0;
  uint64_t bytes_ = 0, requests_ = 0;
  bool anyDone_ = false;
  uint64_t lastDoneId_ = 0, lastDoneAddr_ = 0;
};
