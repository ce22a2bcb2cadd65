// The expected shader-operation results, written by mapm.sim.ExpectedSo (Scala).
//
// File (little-endian): 32-byte header
//   0 magic "MAPMSO01", 8 u32 version 1, 12 u8 exponent width, 13 u8 mantissa width, 14 u16 0,
//   16 u64 record count, 24 u32 image width, 28 u32 image height
// then one 24-byte record per shader operation, sorted by (query, photon):
//   0 u32 query, 4 u32 photon, 8/12/16 u32 colour r/g/b (format bits),
//   20 u16: flags r (bits 0-2), g (3-5), b (6-8), cond (bit 9); 22 u16 0.
// Lookup: the records of query q are [first[q], first[q+1]); the photon is found by binary search.
#pragma once
#include <algorithm>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <string>
#include <vector>

struct SoRecord {
  uint32_t q, photon, colour[3];
  uint16_t flagsCond, pad;
  int flags(int c) const { return (flagsCond >> (3 * c)) & 7; }
  bool cond() const { return (flagsCond >> 9) & 1; }
};
static_assert(sizeof(SoRecord) == 24, "SoRecord must be 24 bytes");

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
    uint8_t h[32];
    if (fread(h, 1, 32, f) != 32 || memcmp(h, "MAPMSO01", 8) != 0) { fclose(f); return path + ": not an expected-SO file"; }
    uint32_t version; uint64_t count;
    memcpy(&version, h + 8, 4); memcpy(&count, h + 16, 8);
    memcpy(&width, h + 24, 4); memcpy(&height, h + 28, 4);
    ew = h[12]; mw = h[13];
    if (version != 1) { fclose(f); return path + ": version " + std::to_string(version) + ", expected 1"; }
    rec.resize(count);
    if (count && fread(rec.data(), sizeof(SoRecord), count, f) != count) { fclose(f); return path + ": truncated"; }
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
