// The memory image (docs/memory-layout.md) as the harness reads it: the header's fields, the query
// records' pixel indices and the query stream, every field through the generated mapm_formats.h
// (mapm.format.MemoryLayout). The slot field of the header (2, 4 or 8 bytes) selects the records'
// layout; it must be the one the hardware was built for (MAPM_SLOT_BYTES).
#pragma once
#include <cstdint>
#include <cstdio>
#include <string>
#include <vector>

#include "mapm_formats.h"

struct Image {
  std::vector<uint8_t> bytes;
  int ew = 0, mw = 0;
  unsigned slot = 4;
  uint32_t nodes = 0, queries = 0;
  uint64_t h = 0, photonBase = 0, queryBase = 0, streamBase = 0;

  // Loads `path`, an image whose format and slots must be `ew`, `mw` and `hwSlot` (the hardware's);
  // returns an error message or "".
  std::string load(const std::string& path, int hwEw, int hwMw, unsigned hwSlot) {
    FILE* f = fopen(path.c_str(), "rb");
    if (!f) return path + ": cannot open";
    fseek(f, 0, SEEK_END);
    long n = ftell(f);
    fseek(f, 0, SEEK_SET);
    bytes.resize(n < 0 ? 0 : n);
    size_t got = fread(bytes.data(), 1, bytes.size(), f);
    fclose(f);
    if (got != bytes.size() || bytes.size() < IMAGE_BYTES || image_magic(bytes.data()) != IMAGE_MAGIC)
      return path + ": not a MAPM memory image";
    const uint8_t* hd = bytes.data();
    if (image_version(hd) != IMAGE_VERSION)
      return path + ": version " + std::to_string(image_version(hd)) + ", expected " + std::to_string(IMAGE_VERSION);
    ew = image_exp_width(hd); mw = image_man_width(hd); slot = image_slot(hd);
    nodes = image_nodes(hd); queries = image_queries(hd); h = image_h(hd);
    photonBase = image_photon_base(hd); queryBase = image_query_base(hd); streamBase = image_stream_base(hd);
    if (image_total_bytes(hd) != bytes.size()) return path + ": size differs from its header";
    if (ew != hwEw || mw != hwMw)
      return path + ": format e" + std::to_string(ew) + "m" + std::to_string(mw) + ", the hardware computes in e" +
             std::to_string(hwEw) + "m" + std::to_string(hwMw);
    if (slot != hwSlot)
      return path + ": records of " + std::to_string(slot) + "-byte slots, the hardware reads " + std::to_string(hwSlot) + "-byte ones";
    return "";
  }
  // The byte ranges the hardware may read: the node, photon and query arrays, each to the start
  // of the next array (its span rounded up to the image's alignment; a cache line never crosses it).
  std::vector<std::pair<uint64_t, uint64_t>> readable() const {
    return {{IMAGE_BYTES, photonBase}, {photonBase, queryBase}, {queryBase, streamBase}};
  }
  uint32_t pixel(uint32_t q) const { return query_pixel(&bytes[queryBase + (uint64_t)query_bytes(slot) * q], slot); }
  // Stream entry k: the index of the query to run.
  uint32_t streamQuery(uint32_t k) const { return stream_query(&bytes[streamBase + (uint64_t)stream_bytes(slot) * k], slot); }
};
