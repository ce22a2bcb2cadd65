// Faults the harness injects on request (`--fault KIND`, docs/harness.md "Injected faults"). Each
// is one the hardware must flag (the bare MAPM on io_error, the coprocessor in ERROR_CAUSE) or the
// bare MAPM's DRAM model must name in its FAIL line (query-index: the SOQ read leaves the query
// array), never hang on or mishandle.
//   node-axis           node 0's split axis set to 3 (no such axis)
//   node-child          node 0 given a right child beyond the node count
//   query-index         the first query sent (the coprocessor: stream entry 0) with an index beyond
//                       the query array
//   unknown-id          one response beat with an id no request is waiting on
//   duplicate-response  the last beat of a finished request sent a second time
// The coprocessor's AXI4 port alone (the bare MAPM's port has no response codes or write channel):
//   early-last          RLAST on a beat that is not its burst's last
//   read-error          one read beat answered SLVERR
//   write-error         one write answered SLVERR
//   stray-b             a write response while no write is outstanding
// The response faults happen once, at the first cycle at or after `--fault-at` where they can.
#pragma once
#include <cstdint>
#include <string>

#include "dram.h"
#include "image.h"
#include "mapm_formats.h"

enum class Fault { None, NodeAxis, NodeChild, QueryIndex, UnknownId, DuplicateResponse, EarlyLast, ReadError, WriteError, StrayB };

// Whether `f` needs the coprocessor's AXI4 port.
inline bool axiOnly(Fault f) { return f == Fault::EarlyLast || f == Fault::ReadError || f == Fault::WriteError || f == Fault::StrayB; }

inline const char* faultName(Fault f) {
  switch (f) {
    case Fault::NodeAxis: return "node-axis";
    case Fault::NodeChild: return "node-child";
    case Fault::QueryIndex: return "query-index";
    case Fault::UnknownId: return "unknown-id";
    case Fault::DuplicateResponse: return "duplicate-response";
    case Fault::EarlyLast: return "early-last";
    case Fault::ReadError: return "read-error";
    case Fault::WriteError: return "write-error";
    case Fault::StrayB: return "stray-b";
    default: return "none";
  }
}

// The fault called `s`; false for an unknown name.
inline bool parseFault(const std::string& s, Fault* f) {
  for (Fault k : {Fault::None, Fault::NodeAxis, Fault::NodeChild, Fault::QueryIndex, Fault::UnknownId, Fault::DuplicateResponse,
                  Fault::EarlyLast, Fault::ReadError, Fault::WriteError, Fault::StrayB})
    if (s == faultName(k)) { *f = k; return true; }
  return false;
}

// Applies an image fault (node-axis, node-child) to the loaded image; returns an error message or "".
inline std::string corruptImage(Fault f, Image& img) {
  if (f != Fault::NodeAxis && f != Fault::NodeChild) return "";
  if (img.nodes == 0) return "--fault " + std::string(faultName(f)) + " needs a tree with a node";
  uint8_t* word = &img.bytes[IMAGE_BYTES + node_word_offset(img.slot)];
  uint32_t w = mapm_le32(word);
  if (f == Fault::NodeAxis) w |= NODE_AXIS_MASK;
  else w = (w & ((1u << NODE_RIGHT_SHIFT) - 1) & ~(uint32_t)NODE_RIGHT_IS_LEAF) | NODE_HAS_RIGHT | ((img.nodes + 7u) << NODE_RIGHT_SHIFT);
  for (int i = 0; i < 4; i++) word[i] = (uint8_t)(w >> (8 * i));
  return "";
}

// Injects a response fault into one cycle's drive: replaces the beat the DRAM offers (which it
// keeps for a later cycle) with the faulty one. Returns true when it did (the beat is not the
// DRAM's: do not report it taken).
class ResponseFault {
 public:
  ResponseFault(Fault f, uint64_t at, int idBits) : fault_(f), at_(at), idBits_(idBits) {}

  bool inject(uint64_t cycle, const Dram& dram, uint8_t* data, int dataBytes, uint64_t* id, bool* last) {
    if (done_ || cycle < at_) return false;
    if (fault_ == Fault::UnknownId) {
      const uint64_t ids = idBits_ >= 63 ? UINT64_MAX : (1ull << idBits_);
      uint64_t k = 0;
      while (k < ids && dram.isOutstanding(k)) k++;
      if (k == ids) return false;
      *id = k;
      for (int i = 0; i < dataBytes; i++) data[i] = 0;
    } else if (fault_ == Fault::DuplicateResponse) {
      if (!dram.lastDone(id, data) || dram.isOutstanding(*id)) return false;
    } else {
      return false;
    }
    *last = true;
    mark(cycle);
    return true;
  }

  // The coprocessor's read faults, on the beat the DRAM offers this cycle (which stays the DRAM's:
  // report it taken as usual): early-last marks a beat that is not its burst's last as last,
  // read-error answers it SLVERR.
  void alterRead(uint64_t cycle, bool offered, bool* last, unsigned* resp) {
    if (done_ || cycle < at_ || !offered) return;
    if (fault_ == Fault::EarlyLast && !*last) { *last = true; mark(cycle); }
    else if (fault_ == Fault::ReadError) { *resp = 2; mark(cycle); }
  }
  // The coprocessor's write faults: write-error answers the offered B SLVERR; stray-b offers a B
  // (id 0) while no write is outstanding and `busy` (a read is, so a pass is running). Returns true
  // when the B is the fault's own, not the memory's.
  bool alterWrite(uint64_t cycle, bool offered, bool writesIdle, bool busy, bool* valid, uint64_t* id, unsigned* resp) {
    if (done_ || cycle < at_) return false;
    if (fault_ == Fault::WriteError && offered) { *resp = 2; mark(cycle); return false; }
    if (fault_ == Fault::StrayB && !offered && writesIdle && busy) { *valid = true; *id = 0; mark(cycle); return true; }
    return false;
  }
  bool injected() const { return done_; }
  uint64_t cycle() const { return cycle_; }

 private:
  Fault fault_;
  uint64_t at_;
  int idBits_;
  bool done_ = false;
  uint64_t cycle_ = 0;
  void mark(uint64_t cycle) { done_ = true; cycle_ = cycle; }
};
