#include "io/dicom/dicom_tags.hpp"

#include <algorithm>
#include <cctype>
#include <charconv>
#include <cmath>
#include <cstring>
#include <mutex>
#include <string_view>

#include <fmt/format.h>
#include <gdcmTrace.h>

#include "intermix/error.hpp"

namespace imx::detail {

void quiet_gdcm() {
  static std::once_flag once;
  std::call_once(once, [] {
    gdcm::Trace::SetDebug(false);
    gdcm::Trace::SetWarning(false);
    gdcm::Trace::SetError(false);
  });
}

std::string tag_name(uint16_t group, uint16_t element) {
  return fmt::format("({:04X},{:04X})", group, element);
}

namespace {

const gdcm::ByteValue* byte_value(const gdcm::DataSet& ds, uint16_t group, uint16_t element) {
  const gdcm::Tag tag(group, element);
  if (!ds.FindDataElement(tag)) return nullptr;
  const gdcm::DataElement& de = ds.GetDataElement(tag);
  if (de.IsEmpty()) return nullptr;
  const gdcm::ByteValue* bv = de.GetByteValue();
  if (bv == nullptr || bv->GetPointer() == nullptr || bv->GetLength() == 0) return nullptr;
  return bv;
}

std::optional<double> parse_number(std::string_view s) {
  while (!s.empty() && std::isspace(static_cast<unsigned char>(s.front()))) s.remove_prefix(1);
  while (!s.empty() && std::isspace(static_cast<unsigned char>(s.back()))) s.remove_suffix(1);
  if (!s.empty() && s.front() == '+') s.remove_prefix(1);
  if (s.empty()) return std::nullopt;
  double v = 0.0;
  auto [end, ec] = std::from_chars(s.data(), s.data() + s.size(), v);
  if (ec != std::errc() || end != s.data() + s.size() || !std::isfinite(v)) return std::nullopt;
  return v;
}

}  // namespace

std::optional<std::string> tag_text(const gdcm::DataSet& ds, uint16_t group, uint16_t element) {
  const gdcm::ByteValue* bv = byte_value(ds, group, element);
  if (bv == nullptr) return std::nullopt;
  std::string s(bv->GetPointer(), bv->GetLength());
  while (!s.empty() && (s.back() == ' ' || s.back() == '\0')) s.pop_back();
  s.erase(0, std::min(s.size(), s.find_first_not_of(' ')));  // at once: linear in the padding
  if (s.empty()) return std::nullopt;
  return s;
}

std::vector<double> tag_numbers(const gdcm::DataSet& ds, uint16_t group, uint16_t element) {
  std::optional<std::string> text = tag_text(ds, group, element);
  std::vector<double> out;
  if (!text) return out;
  std::string_view rest = *text;
  while (true) {
    size_t cut = rest.find('\\');
    std::optional<double> v = parse_number(rest.substr(0, cut));
    if (!v) return {};
    out.push_back(*v);
    if (cut == std::string_view::npos) break;
    rest.remove_prefix(cut + 1);
  }
  return out;
}

std::optional<double> tag_number(const gdcm::DataSet& ds, uint16_t group, uint16_t element) {
  std::vector<double> v = tag_numbers(ds, group, element);
  if (v.empty()) return std::nullopt;
  return v.front();
}

std::string unusable_message(const std::string& file, const char* name, uint16_t group,
                             uint16_t element, const std::string& value, const char* why) {
  // Values come from the file: shown shortened and with control bytes escaped.
  std::string shown;
  for (char c : value.substr(0, 64))
    shown += std::isprint(static_cast<unsigned char>(c)) ? std::string(1, c)
                                                         : fmt::format("\\x{:02x}", c & 0xff);
  if (value.size() > 64) shown += "...";
  return fmt::format("{}: {} {} is present but unusable: '{}' ({})", file, name,
                     tag_name(group, element), shown, why);
}

std::optional<std::vector<double>> used_numbers(const gdcm::DataSet& ds, uint16_t group,
                                                uint16_t element, const std::string& file,
                                                const char* name, const char* why,
                                                bool (*usable)(double)) {
  std::optional<std::string> text = tag_text(ds, group, element);
  if (!text) return std::nullopt;
  std::vector<double> values = tag_numbers(ds, group, element);
  const bool ok =
      !values.empty() && (usable == nullptr || std::all_of(values.begin(), values.end(), usable));
  if (!ok) throw Error(unusable_message(file, name, group, element, *text, why));
  return values;
}

std::optional<int> tag_us(const gdcm::DataSet& ds, uint16_t group, uint16_t element) {
  const gdcm::ByteValue* bv = byte_value(ds, group, element);
  if (bv == nullptr || bv->GetLength() < 2) return std::nullopt;
  uint16_t v = 0;
  std::memcpy(&v, bv->GetPointer(), sizeof v);
  return static_cast<int>(v);
}

namespace {

template <class T>
std::vector<T> binary_values(const gdcm::DataSet& ds, uint16_t group, uint16_t element) {
  const gdcm::ByteValue* bv = byte_value(ds, group, element);
  if (bv == nullptr || bv->GetLength() % sizeof(T) != 0) return {};
  std::vector<T> out(bv->GetLength() / sizeof(T));
  std::memcpy(out.data(), bv->GetPointer(), out.size() * sizeof(T));
  return out;
}

template <class T>
std::vector<double> finite_values(const gdcm::DataSet& ds, uint16_t group, uint16_t element) {
  std::vector<double> out;
  for (T v : binary_values<T>(ds, group, element)) {
    if (!std::isfinite(v)) return {};
    out.push_back(static_cast<double>(v));
  }
  return out;
}

}  // namespace

std::vector<double> tag_fd(const gdcm::DataSet& ds, uint16_t group, uint16_t element) {
  return finite_values<double>(ds, group, element);
}

std::vector<double> tag_fl(const gdcm::DataSet& ds, uint16_t group, uint16_t element) {
  return finite_values<float>(ds, group, element);
}

std::vector<uint32_t> tag_ul(const gdcm::DataSet& ds, uint16_t group, uint16_t element) {
  return binary_values<uint32_t>(ds, group, element);
}

std::string tag_bytes(const gdcm::DataSet& ds, uint16_t group, uint16_t element) {
  const gdcm::ByteValue* bv = byte_value(ds, group, element);
  return bv == nullptr ? std::string() : std::string(bv->GetPointer(), bv->GetLength());
}

std::optional<uint16_t> private_block(const gdcm::DataSet& ds, uint16_t group,
                                      const std::string& creator) {
  for (uint16_t e = 0x10; e <= 0xff; ++e)
    if (auto name = tag_text(ds, group, e); name && *name == creator)
      return static_cast<uint16_t>(e << 8);
  return std::nullopt;
}

gdcm::SmartPointer<gdcm::SequenceOfItems> tag_sequence(const gdcm::DataSet& ds, uint16_t group,
                                                       uint16_t element) {
  const gdcm::Tag tag(group, element);
  if (!ds.FindDataElement(tag)) return nullptr;
  try {
    gdcm::SmartPointer<gdcm::SequenceOfItems> sq = ds.GetDataElement(tag).GetValueAsSQ();
    if (sq && sq->GetNumberOfItems() == 0) return nullptr;
    return sq;
  } catch (...) {  // GDCM parses undefined-VR sequences on demand and may throw on bad bytes
    return nullptr;
  }
}

std::string transfer_syntax_label(const std::string& uid) {
  static const std::pair<const char*, const char*> kNames[] = {
      {"1.2.840.10008.1.2", "Implicit VR Little Endian"},
      {"1.2.840.10008.1.2.1", "Explicit VR Little Endian"},
      {"1.2.840.10008.1.2.1.99", "Deflated Explicit VR Little Endian"},
      {"1.2.840.10008.1.2.2", "Explicit VR Big Endian"},
      {"1.2.840.10008.1.2.5", "RLE Lossless"},
      {"1.2.840.10008.1.2.4.50", "JPEG Baseline"},
      {"1.2.840.10008.1.2.4.51", "JPEG Extended"},
      {"1.2.840.10008.1.2.4.57", "JPEG Lossless"},
      {"1.2.840.10008.1.2.4.70", "JPEG Lossless, first-order prediction"},
      {"1.2.840.10008.1.2.4.80", "JPEG-LS Lossless"},
      {"1.2.840.10008.1.2.4.81", "JPEG-LS Near-Lossless"},
      {"1.2.840.10008.1.2.4.90", "JPEG 2000 Lossless"},
      {"1.2.840.10008.1.2.4.91", "JPEG 2000"},
  };
  for (const auto& [id, name] : kNames)
    if (uid == id) return fmt::format("{} ({})", uid, name);
  return uid;
}

std::optional<double> parse_dicom_time(const std::string& tm) {
  std::string digits;
  size_t i = 0;
  for (; i < tm.size() && tm[i] != '.'; ++i) {
    if (tm[i] == ':') continue;  // the old ACR-NEMA form HH:MM:SS
    if (!std::isdigit(static_cast<unsigned char>(tm[i]))) return std::nullopt;
    digits.push_back(tm[i]);
  }
  if (digits.size() < 2 || digits.size() > 6 || digits.size() % 2 != 0) return std::nullopt;
  int h = std::stoi(digits.substr(0, 2));
  int m = digits.size() >= 4 ? std::stoi(digits.substr(2, 2)) : 0;
  int s = digits.size() >= 6 ? std::stoi(digits.substr(4, 2)) : 0;
  if (h > 23 || m > 59 || s > 60) return std::nullopt;
  double fraction = 0.0;
  if (i < tm.size()) {
    std::string frac = tm.substr(i);  // ".123456"
    if (frac.size() > 7) return std::nullopt;
    for (size_t k = 1; k < frac.size(); ++k)
      if (!std::isdigit(static_cast<unsigned char>(frac[k]))) return std::nullopt;
    if (frac.size() > 1) fraction = std::stod("0" + frac);
  }
  return h * 3600.0 + m * 60.0 + s + fraction;
}

}  // namespace imx::detail
