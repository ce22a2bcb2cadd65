// Output files of the harness: the frame (PFM and raw doubles) and a small JSON writer.
#pragma once
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <string>
#include <vector>

// PFM as mapm.model.ImageIO writes it: "PF\n<w> <h>\n-1.0\n", little-endian float RGB,
// rows bottom to top. rgb[3 * (y * w + x) + c].
inline bool writePfm(const std::string& path, const std::vector<double>& rgb, uint32_t w, uint32_t h) {
  FILE* f = fopen(path.c_str(), "wb");
  if (!f) return false;
  fprintf(f, "PF\n%u %u\n-1.0\n", w, h);
  std::vector<float> row(3 * (size_t)w);
  for (int64_t y = (int64_t)h - 1; y >= 0; y--) {
    for (size_t i = 0; i < row.size(); i++) row[i] = (float)rgb[3 * (size_t)y * w + i];
    fwrite(row.data(), sizeof(float), row.size(), f);
  }
  return fclose(f) == 0;
}

// The frame as little-endian doubles, row-major from the top-left pixel, 3 per pixel: the
// exact accumulation's values, for a bit-exact comparison with the model frame.
inline bool writeDoubles(const std::string& path, const std::vector<double>& rgb) {
  FILE* f = fopen(path.c_str(), "wb");
  if (!f) return false;
  fwrite(rgb.data(), sizeof(double), rgb.size(), f);
  return fclose(f) == 0;
}

// A flat JSON object writer (nested objects through begin/end).
class Json {
 public:
  void begin(const std::string& key = "") { sep(); if (!key.empty()) s_ += quote(key) + ": "; s_ += "{"; first_ = true; depth_++; }
  void end() { depth_--; s_ += "\n" + std::string(2 * depth_, ' ') + "}"; first_ = false; }
  void num(const std::string& key, double v) {
    sep();
    char b[64];
    if (std::isfinite(v)) snprintf(b, sizeof b, "%.17g", v); else snprintf(b, sizeof b, "null");
    s_ += quote(key) + ": " + b;
  }
  void integer(const std::string& key, uint64_t v) { sep(); s_ += quote(key) + ": " + std::to_string(v); }
  void str(const std::string& key, const std::string& v) { sep(); s_ += quote(key) + ": " + quote(v); }
  void null(const std::string& key) { sep(); s_ += quote(key) + ": null"; }
  std::string text() const { return s_ + "\n"; }

 private:
  void sep() {
    if (depth_ == 0) return;
    s_ += first_ ? "\n" : ",\n";
    s_ += std::string(2 * depth_, ' ');
    first_ = false;
  }
  static std::string quote(const std::string& v) {
    std::string r = "\"";
    for (char c : v) {
      if (c == '"' || c == '\\') { r += '\\'; r += c; }
      else if ((unsigned char)c < 0x20) { char b[8]; snprintf(b, sizeof b, "\\u%04x", c); r += b; }
      else r += c;
    }
    return r + "\"";
  }
  std::string s_;
  bool first_ = true;
  int depth_ = 0;
};
