// The expected shader-operation results, written by mapm.sim.ExpectedSo (Scala) in the format of
// mapm.format.ExpectedSoFile (docs/harness.md), read through the generated mapm_formats.h: a
// header (format, colour field size, record count, image size), then one record per SO sorted by
// (query, photon); colours take 4 bytes up to 32-bit formats, 8 above.
// Lookup: the records of query q are [first[q], first[q+1]); the photon is found by binary search.
#pragma once
#include <algorithm>
#include <cstdint>
#include <cstdio>
#include <string>
#include <vector>

#include "mapm_formats.h"

struct SoRecord {
  uint32_t q, photon;
  uint64_t colour[3];
  uint16_t flagsCond;
  int flags(int c) const { return (flagsCond >> (SO_FLAG_BITS * c)) & ((1 << SO_FLAG_BITS) - 1); }
  bool cond() const { return (flagsCond >> SO_COND_BIT) & 1; }
};

class Expected {
 public:
  int ew = 0, mw = 0;
  uint32_t width = 0, height = 0;
  std::vector<SoRecord> rec;
  std::vector<uint64_t> first;  // per query, plus one
  std::vector<uint8_t> seen;
  std::vector<uint32_t> remaining;  // per query: expected SOs not yet seen

  // Loads `path` for `queries` queries; returns an error message or "".
  std::string load(const std::string& path, uint32_t queries) {
    FILE* f = fopen(path.c_str(), "rb");
    if (!f) return path + ": cannot open";
    uint8_t h[EXPECTED_BYTES];
    if (fread(h, 1, EXPECTED_BYTES, f) != EXPECTED_BYTES || expected_magic(h) != EXPECTED_MAGIC) {
      fclose(f);
      return path + ": not an expected-SO file";
    }
    if (expected_version(h) != EXPECTED_VERSION) {
      fclose(f);
      return path + ": version " + std::to_string(expected_version(h)) + ", expected " + std::to_string(EXPECTED_VERSION);
    }
    const uint64_t count = expected_count(h);
    width = expected_width(h); height = expected_height(h);
    ew = expected_exp_width(h); mw = expected_man_width(h);
    const unsigned cb = expected_colour_bytes(h);
    if (cb != (1 + ew + mw <= 32 ? 4u : 8u)) {
      fclose(f);
      return path + ": colour fields of " + std::to_string(cb) + " bytes for a " + std::to_string(1 + ew + mw) + "-bit format";
    }
    const uint32_t bytes = so_bytes(cb);
    rec.resize(count);
    std::vector<uint8_t> chunk(bytes * 65536);
    for (uint64_t i = 0; i < count;) {
      const uint64_t n = std::min<uint64_t>(count - i, 65536);
      if (fread(chunk.data(), bytes, n, f) != n) { fclose(f); return path + ": truncated"; }
      for (uint64_t k = 0; k < n; k++, i++) {
        const uint8_t* r = &chunk[bytes * k];
        rec[i] = {so_query(r, cb), so_photon(r, cb), {so_colour_r(r, cb), so_colour_g(r, cb), so_colour_b(r, cb)}, so_flags(r, cb)};
      }
    }
    fclose(f);
    first.assign(queries + 1, 0);
    remaining.assign(queries, 0);
    for (uint64_t i = 0; i < count; i++) {
      const SoRecord& r = rec[i];
      if (r.q >= queries) return path + ": record " + std::to_string(i) + " names query " + std::to_string(r.q) + " beyond the image's " + std::to_string(queries);
      if (i && (rec[i - 1].q > r.q || (rec[i - 1].q == r.q && rec[i - 1].photon > r.photon)))
        return path + ": records not sorted by (query, photon) at " + std::to_string(i);
      first[r.q + 1]++;
      remaining[r.q]++;
    }
    for (uint32_t q = 0; q < queries; q++) first[q + 1] += first[q];
    seen.assign(count, 0);
    return "";
  }

  // Finds an unseen record of (q, photon), marks it seen and returns its index; -1 when there is
  // none, with *duplicate set when every matching record was seen already.
  int64_t take(uint64_t q, uint64_t photon, bool* duplicate) {
    *duplicate = false;
    if (q + 1 >= first.size()) return -1;
    auto lo = rec.begin() + first[q], hi = rec.begin() + first[q + 1];
    auto it = std::lower_bound(lo, hi, photon, [](const SoRecord& r, uint64_t p) { return r.photon < p; });
    for (; it != hi && it->photon == photon; ++it) {
      size_t i = it - rec.begin();
      if (!seen[i]) { seen[i] = 1; remaining[q]--; return (int64_t)i; }
      *duplicate = true;
    }
    return -1;
  }
};
