// Checks the top's result beats against the expected SOs (and each beat's pixel against its query
// record's), adds the colours of those whose cond
// holds into their pixels exactly, and counts the queries complete (taken, every SO seen).
// With MAPM_FIDELITY_TIMING (SOAs replaced by their timing model, which computes no colour) a beat
// is checked for its (q, photon) alone, and its colour, flags and cond are the expected SO's.
#pragma once
#include <cstdint>
#include <cstdio>
#include <string>
#include <vector>

#include "accum.h"
#include "expected.h"
#include "image.h"
#include "mapm_config.h"

class Checker {
 public:
  Checker(Expected& exp, const Image& img, uint64_t pixels)
      : acc(ExactFormat(img.ew, img.mw), 3 * pixels), exp_(exp), img_(img), queryDone_(img.queries, 0) {}

  // Query q was taken by the hardware.
  void taken(uint32_t q) { complete(q); }

  // Checks the beat `o` of port `port` in `cycle`; returns a failure message or "".
  std::string beat(const OutBeat& o, int port, uint64_t cycle) {
    bool dup = false;
    const int64_t i = exp_.take(o.q, o.photon, &dup);
    auto so = [&] {
      return "SO (q=" + std::to_string(o.q) + ", photon=" + std::to_string(o.photon) + ") on port " + std::to_string(port) +
             " at cycle " + std::to_string(cycle);
    };
    if (i < 0) return (dup ? "duplicate " : "unexpected ") + so() + ": " + describe(o);
    const SoRecord& r = exp_.rec[i];
    if (o.pixel != img_.pixel(o.q))
      return "wrong pixel on " + so() + ": " + std::to_string(o.pixel) + ", its query record says " + std::to_string(img_.pixel(o.q));
#if MAPM_FIDELITY_TIMING
#ifdef MAPM_COPROC
    // The coprocessor's timing model computes cond (its accumulator takes the passing SOs).
    if (o.cond != r.cond()) return "mismatch " + so() + ": cond " + std::to_string(o.cond) + ", expected " + std::to_string(r.cond());
#endif
    const bool cond = r.cond();
    const uint64_t* colour = r.colour;
#else
    bool same = o.cond == r.cond();
    for (int c = 0; c < 3; c++) same = same && o.colour[c] == r.colour[c] && o.flags[c] == (uint32_t)r.flags(c);
    if (!same) return "mismatch " + so() + ": got " + describe(o) + "; expected " + describe(r);
    const bool cond = o.cond;
    const uint64_t* colour = o.colour;
#endif
    soOut++;
    if (cond) {
      soPassed++;
      const uint64_t px = img_.pixel(o.q);
      for (int c = 0; c < 3; c++) acc.add(3 * px + c, colour[c]);
    }
    complete((uint32_t)o.q);
    return "";
  }

  // After the run: the expected SOs that never came out, as a failure message, or "".
  std::string missing() const {
    uint64_t count = 0, first = 0;
    for (uint64_t i = exp_.rec.size(); i-- > 0;)
      if (!exp_.seen[i]) { count++; first = i; }
    if (!count) return "";
    return std::to_string(count) + " expected SOs never came out (first: q=" + std::to_string(exp_.rec[first].q) +
           ", photon=" + std::to_string(exp_.rec[first].photon) + ")";
  }

  // Counts the queries with every SO seen that nobody reported taken (the coprocessor reads its
  // own stream, so the harness never sees a query taken).
  void completeAll() { for (uint32_t q = 0; q < queryDone_.size(); q++) complete(q); }

  ExactAccumulators acc;
  uint64_t soOut = 0, soPassed = 0, completed = 0;

 private:
  void complete(uint32_t q) { if (!queryDone_[q] && exp_.remaining[q] == 0) { queryDone_[q] = 1; completed++; } }

  static std::string hexs(uint64_t v) { char b[24]; snprintf(b, sizeof b, "0x%llx", (unsigned long long)v); return b; }
  static std::string describe(const OutBeat& o) {
    return "colour " + hexs(o.colour[0]) + " " + hexs(o.colour[1]) + " " + hexs(o.colour[2]) + ", flags " +
           std::to_string(o.flags[0]) + " " + std::to_string(o.flags[1]) + " " + std::to_string(o.flags[2]) + ", cond " +
           std::to_string(o.cond);
  }
  static std::string describe(const SoRecord& r) {
    return "colour " + hexs(r.colour[0]) + " " + hexs(r.colour[1]) + " " + hexs(r.colour[2]) + ", flags " +
           std::to_string(r.flags(0)) + " " + std::to_string(r.flags(1)) + " " + std::to_string(r.flags(2)) + ", cond " +
           std::to_string(r.cond());
  }

  Expected& exp_;
  const Image& img_;
  std::vector<uint8_t> queryDone_;
};
