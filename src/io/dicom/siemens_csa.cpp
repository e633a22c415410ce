#include "io/dicom/siemens_csa.hpp"

#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstring>

namespace imx::detail {

namespace {

constexpr uint32_t kMaxCsaElements = 512;  // real headers hold about 100
constexpr uint32_t kMaxCsaItems = 512;

// A little-endian reader that stops (ok() false) rather than reading past the end.
struct Cursor {
  const std::string& bytes;
  size_t at = 0;
  bool good = true;

  uint32_t u32() {
    if (!good || bytes.size() - at < 4 || at > bytes.size()) {
      good = false;
      return 0;
    }
    uint32_t v;
    std::memcpy(&v, bytes.data() + at, 4);
    at += 4;
    return v;
  }
  std::string text(size_t length) {
    if (!good || at > bytes.size() || bytes.size() - at < length) {
      good = false;
      return {};
    }
    std::string s(bytes.data() + at, length);
    at += length;
    s.resize(std::strlen(s.c_str()));  // NUL-terminated within its field
    return s;
  }
};

std::string trimmed(std::string s) {
  while (!s.empty() && (s.back() == ' ' || s.back() == '\0')) s.pop_back();
  size_t start = s.find_first_not_of(' ');
  return start == std::string::npos ? std::string() : s.substr(start);
}

}  // namespace

std::map<std::string, std::vector<std::string>> parse_csa_header(const std::string& bytes) {
  std::map<std::string, std::vector<std::string>> out;
  Cursor c{bytes};
  if (bytes.size() >= 8 && bytes.compare(0, 4, "SV10") == 0) c.at = 8;  // "SV10" and 4 bytes
  const uint32_t elements = c.u32();
  c.u32();  // always 77
  if (!c.good || elements > kMaxCsaElements) return out;
  for (uint32_t e = 0; e < elements && c.good; ++e) {
    std::string name = c.text(64);
    c.u32();    // VM
    c.text(4);  // VR
    c.u32();    // SyngoDT
    const uint32_t items = c.u32();
    c.u32();  // 77 or 205
    if (!c.good || items > kMaxCsaItems) break;
    std::vector<std::string> values;
    for (uint32_t i = 0; i < items && c.good; ++i) {
      c.u32();
      const uint32_t length = c.u32();
      c.u32();
      c.u32();
      if (!c.good || length > bytes.size()) {
        c.good = false;
        break;
      }
      std::string value = trimmed(c.text(length));
      c.text((4 - length % 4) % 4);  // items are padded to 4 bytes
      if (!value.empty()) values.push_back(std::move(value));
    }
    if (c.good && !name.empty()) out[name] = std::move(values);
  }
  return out;
}

std::optional<std::vector<double>> csa_numbers(
    const std::map<std::string, std::vector<std::string>>& csa, const std::string& name) {
  auto it = csa.find(name);
  if (it == csa.end() || it->second.empty()) return std::nullopt;
  std::vector<double> out;
  for (const std::string& s : it->second) {
    double v = 0.0;
    auto [end, ec] = std::from_chars(s.data(), s.data() + s.size(), v);
    if (ec != std::errc() || end != s.data() + s.size() || !std::isfinite(v)) return std::nullopt;
    out.push_back(v);
  }
  return out;
}

}  // namespace imx::detail
