// Exact, order-independent accumulation of float-format values (mapm Verilator harness).
//
// A value of format (ew, mw) with exponent field E >= 1 and fraction M is
// (2^mw + M) * 2^(E - 1) units of 2^(1 - bias - mw): an integer. The accumulator keeps that
// integer sum exactly in 32-bit limbs held in int64: the significand (< 2^53) shifted by
// (E - 1) % 32 spans up to three limbs, so each add puts < 2^32 into each of three limbs, and 2^30
// adds fit before carries must be propagated. Every format up to 64 bits wide (ew <= 11,
// mw <= 52, e.g. fp64) is taken. Exponent field 0 is zero (the formats flush subnormals);
// all-ones (infinity, NaN) makes the sum NaN. The sum is rounded to a double once (nearest, ties
// to even) by toDouble(). mapm.sim.ExactSum is the same algorithm in Scala, so the harness frame
// and the model frame are bit-equal whatever the order of the additions.
#pragma once
#include <cmath>
#include <cstdint>
#include <vector>

class ExactFormat {
 public:
  ExactFormat(int ew, int mw)
      : ew_(ew), mw_(mw), bias_((1 << (ew - 1)) - 1),
        limbs_(((1 << ew) + mw + 1) / 32 + 3) {}
  // A value is below 2^(2^ew + mw - 2), so it lies in limbs 0 to limbs - 3; the highest limb an
  // add writes, (2^ew - 3) / 32 + 2, is at most limbs - 1, and what it writes above limbs - 3 is
  // zero. The two top limbs only gather carries and the sign: normalized, the sum is a two's
  // complement number of 32 * limbs bits (at least 2^ew + mw + 66), room for 2^67 adds.
  int limbs() const { return limbs_; }
  int expAllOnes() const { return (1 << ew_) - 1; }
  int ew() const { return ew_; }
  int mw() const { return mw_; }
  // log2 of the unit the integer sum counts.
  int unitExp() const { return 1 - bias_ - mw_; }

 private:
  int ew_, mw_, bias_, limbs_;
};

// A block of accumulators (e.g. 3 per pixel), all of one format, in one flat array.
class ExactAccumulators {
 public:
  ExactAccumulators(const ExactFormat& f, size_t count)
      : f_(f), n_(f.limbs()), limb_(count * f.limbs(), 0), adds_(count, 0), nan_(count, 0) {}

  void add(size_t i, uint64_t bits) {
    const int ew = f_.ew(), mw = f_.mw();
    const uint64_t e = (bits >> mw) & ((1ull << ew) - 1);
    const uint64_t m = bits & ((1ull << mw) - 1);
    const bool neg = (bits >> (ew + mw)) & 1;
    if (e == 0) return;
    if (e == (uint64_t)f_.expAllOnes()) { nan_[i] = 1; return; }
    const uint64_t sig = (1ull << mw) | m;  // < 2^53
    const int shift = (int)(e - 1);
    const int r = shift % 32;
    // sig << r (< 2^84) as three parts < 2^32: bits 0-31 and 32-63 of the 64-bit shift (the bits
    // it drops are the third part's), and bits 64-83 as (sig >> 32) >> (32 - r), whose shifts are
    // 32 at most: a single shift by 64 - r would be undefined at r = 0, where the part must be 0.
    const uint64_t v = sig << r;
    const int64_t p0 = (int64_t)(v & 0xffffffffu), p1 = (int64_t)(v >> 32);
    const int64_t p2 = (int64_t)((sig >> 32) >> (32 - r));
    int64_t* l = &limb_[i * n_ + shift / 32];
    if (neg) { l[0] -= p0; l[1] -= p1; l[2] -= p2; } else { l[0] += p0; l[1] += p1; l[2] += p2; }
    if (++adds_[i] == (1u << 30)) { normalize(i); adds_[i] = 0; }
  }

  // The exact sum rounded once to the nearest double (ties to even).
  double toDouble(size_t i) {
    if (nan_[i]) return std::nan("");
    normalize(i);
    std::vector<int64_t> mag(limb_.begin() + i * n_, limb_.begin() + (i + 1) * n_);
    bool neg = mag[n_ - 1] < 0;
    if (neg) {  // two's complement negate over 32-bit limbs
      int64_t carry = 1;
      for (int k = 0; k < n_; k++) {
        int64_t v = ((~mag[k]) & 0xffffffff) + carry;
        mag[k] = v & 0xffffffff;
        carry = v >> 32;
      }
    }
    int top = -1;  // highest set bit
    for (int k = n_ - 1; k >= 0 && top < 0; k--)
      if (mag[k]) top = 32 * k + 63 - __builtin_clzll((uint64_t)mag[k]);
    if (top < 0) return neg ? -0.0 : 0.0;
    auto bit = [&](int b) -> uint64_t { return b < 0 ? 0 : ((uint64_t)mag[b / 32] >> (b % 32)) & 1; };
    uint64_t mant = 0;
    const int lowest = top - 52;  // bit position of the mantissa's LSB
    for (int b = top; b >= lowest; b--) mant = (mant << 1) | bit(b);
    bool round = bit(lowest - 1), sticky = false;
    if (lowest >= 2) {  // any bit below the round bit: those of its limb, then whole limbs
      const int rb = lowest - 1;
      sticky = ((uint64_t)mag[rb / 32] & ((1ull << (rb % 32)) - 1)) != 0;
      for (int k = rb / 32 - 1; k >= 0 && !sticky; k--) sticky = mag[k] != 0;
    }
    if (round && (sticky || (mant & 1))) mant++;
    double r = std::ldexp((double)mant, lowest + f_.unitExp());
    return neg ? -r : r;
  }

 private:
  void normalize(size_t i) {
    int64_t* l = &limb_[i * n_];
    for (int k = 0; k + 1 < n_; k++) {
      int64_t c = l[k] >> 32;  // arithmetic shift: floor division by 2^32
      l[k] -= c * (int64_t(1) << 32);
      l[k + 1] += c;
    }
  }

  ExactFormat f_;
  int n_;
  std::vector<int64_t> limb_;
  std::vector<uint32_t> adds_;
  std::vector<uint8_t> nan_;
};
