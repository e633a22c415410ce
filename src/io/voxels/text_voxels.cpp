#include "io/voxels/text_voxels.hpp"

#include <cfloat>
#include <charconv>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <limits>
#include <optional>
#include <utility>

#include <fmt/format.h>

#include "intermix/error.hpp"
#include "io/streams/header_text.hpp"

namespace imx::detail {

namespace {

// Longer "numbers" are binary data or junk; the message shows their start.
constexpr size_t kMaxToken = 256;

bool is_separator(int c) {
  return c == ' ' || c == '\t' || c == '\n' || c == '\r' || c == '\v' || c == '\f' || c == ',';
}

bool is_space(int c) {
  return c == ' ' || c == '\t' || c == '\n' || c == '\r' || c == '\v' || c == '\f';
}

std::string_view without_plus(std::string_view s) {
  if (s.size() > 1 && s.front() == '+' && s[1] != '-' && s[1] != '+') s.remove_prefix(1);
  return s;
}

// The whole of `s` as an integer of type T, or nothing.
template <class T>
std::optional<T> whole_integer(std::string_view s) {
  T v{};
  auto [end, ec] = std::from_chars(s.data(), s.data() + s.size(), v);
  if (ec != std::errc() || end != s.data() + s.size()) return std::nullopt;
  return v;
}

enum class Parsed { ok, not_a_number, out_of_range };

// The whole of `s` as a double. from_chars reports both overflow and underflow as out of
// range; strtod tells them apart, so that 1e-400 reads as 0 as C's own readers read it.
Parsed whole_double(std::string_view s, double& v) {
  auto [end, ec] = std::from_chars(s.data(), s.data() + s.size(), v);
  if (end != s.data() + s.size() || s.empty()) return Parsed::not_a_number;
  if (ec == std::errc::result_out_of_range) {
    const std::string copy(s);
    v = std::strtod(copy.c_str(), nullptr);
    return std::isinf(v) ? Parsed::out_of_range : Parsed::ok;
  }
  return ec == std::errc() ? Parsed::ok : Parsed::not_a_number;
}

template <class T>
void store(uint8_t* dst, T v) {
  std::memcpy(dst, &v, sizeof(T));
}

}  // namespace

AsciiValues::AsciiValues(std::istream& in, RawType type, std::string what)
    : in_(*in.rdbuf()), type_(type), what_(std::move(what)) {}

bool AsciiValues::next_token() {
  token_.clear();
  int c = in_.sgetc();
  while (c != std::char_traits<char>::eof() && is_separator(c)) c = in_.snextc();
  while (c != std::char_traits<char>::eof() && !is_separator(c)) {
    if (token_.size() >= kMaxToken)
      throw Error(
          fmt::format("{}: ASCII value {} '{}' is not a number", what_, index_, shown(token_)));
    token_.push_back(static_cast<char>(c));
    c = in_.snextc();
  }
  return !token_.empty();
}

void AsciiValues::decode(uint8_t* dst) {
  const std::string_view s = without_plus(token_);
  auto fail = [&](const std::string& why) {
    return Error(fmt::format("{}: ASCII value {} '{}' {}", what_, index_, shown(token_), why));
  };
  const bool is_float = type_ == RawType::f32 || type_ == RawType::f64;
  if (is_float) {
    double v = 0.0;
    const Parsed p = whole_double(s, v);
    if (p == Parsed::not_a_number) throw fail("is not a number");
    if (p == Parsed::out_of_range ||
        (type_ == RawType::f32 && std::isfinite(v) && std::abs(v) > static_cast<double>(FLT_MAX)))
      throw fail(fmt::format("is out of range for {}", raw_type_name(type_)));
    if (type_ == RawType::f32)
      store(dst, static_cast<float>(v));
    else
      store(dst, v);
    return;
  }
  // Integers: exactly, or through a double when written with a point or an exponent.
  long double lo = 0, hi = 0;  // the type's range
  switch (type_) {
    case RawType::i8:
      lo = INT8_MIN, hi = INT8_MAX;
      break;
    case RawType::u8:
      lo = 0, hi = UINT8_MAX;
      break;
    case RawType::i16:
      lo = INT16_MIN, hi = INT16_MAX;
      break;
    case RawType::u16:
      lo = 0, hi = UINT16_MAX;
      break;
    case RawType::i32:
      lo = INT32_MIN, hi = INT32_MAX;
      break;
    case RawType::u32:
      lo = 0, hi = UINT32_MAX;
      break;
    case RawType::i64:
      lo = static_cast<long double>(INT64_MIN), hi = static_cast<long double>(INT64_MAX);
      break;
    default:
      lo = 0, hi = static_cast<long double>(UINT64_MAX);
      break;
  }
  const bool is_unsigned = type_ == RawType::u8 || type_ == RawType::u16 || type_ == RawType::u32 ||
                           type_ == RawType::u64;
  std::optional<long long> signed_value;
  std::optional<unsigned long long> unsigned_value;
  if (is_unsigned)
    unsigned_value = whole_integer<unsigned long long>(s);
  else
    signed_value = whole_integer<long long>(s);
  if (!signed_value && !unsigned_value) {
    double v = 0.0;
    const Parsed p = whole_double(s, v);
    if (p == Parsed::not_a_number || std::isnan(v)) throw fail("is not a number");
    if (p == Parsed::out_of_range || std::isinf(v) || v < static_cast<double>(lo) ||
        v > static_cast<double>(hi) ||
        // 2^63 and 2^64 are the first doubles past the 64-bit ranges.
        (type_ == RawType::i64 && v >= 9223372036854775808.0) ||
        (type_ == RawType::u64 && v >= 18446744073709551616.0))
      throw fail(fmt::format("is out of range for {}", raw_type_name(type_)));
    if (v != std::trunc(v))
      throw fail(fmt::format("is not a whole number, as type {} needs", raw_type_name(type_)));
    if (is_unsigned)
      unsigned_value = static_cast<unsigned long long>(v);
    else
      signed_value = static_cast<long long>(v);
  }
  const long double value = is_unsigned ? static_cast<long double>(*unsigned_value)
                                        : static_cast<long double>(*signed_value);
  if (value < lo || value > hi)
    throw fail(fmt::format("is out of range for {}", raw_type_name(type_)));
  switch (type_) {
    case RawType::i8:
      store(dst, static_cast<int8_t>(*signed_value));
      break;
    case RawType::u8:
      store(dst, static_cast<uint8_t>(*unsigned_value));
      break;
    case RawType::i16:
      store(dst, static_cast<int16_t>(*signed_value));
      break;
    case RawType::u16:
      store(dst, static_cast<uint16_t>(*unsigned_value));
      break;
    case RawType::i32:
      store(dst, static_cast<int32_t>(*signed_value));
      break;
    case RawType::u32:
      store(dst, static_cast<uint32_t>(*unsigned_value));
      break;
    case RawType::i64:
      store(dst, static_cast<int64_t>(*signed_value));
      break;
    default:
      store(dst, static_cast<uint64_t>(*unsigned_value));
      break;
  }
}

void AsciiValues::read(std::span<uint8_t> out, uint64_t expected) {
  const size_t size = raw_type_size(type_);
  for (size_t at = 0; at + size <= out.size(); at += size) {
    if (!next_token())
      throw Error(
          fmt::format("{}: the ASCII data ends after {} values; the header's 'sizes' "
                      "give {}",
                      what_, index_, expected));
    decode(out.data() + at);
    ++index_;
  }
}

void AsciiValues::skip(uint64_t count, uint64_t expected) {
  uint8_t element[8];
  const size_t size = raw_type_size(type_);
  for (uint64_t i = 0; i < count; ++i) read(std::span<uint8_t>(element, size), expected);
}

void AsciiValues::expect_end(uint64_t expected) {
  if (next_token())
    throw Error(
        fmt::format("{}: the ASCII data holds more than the {} values the header's 'sizes' give "
                    "(value {} is '{}')",
                    what_, expected, index_, shown(token_)));
}

HexBytes::HexBytes(std::istream& in, std::string what) : in_(*in.rdbuf()), what_(std::move(what)) {}

int HexBytes::next_digit() {
  int c = in_.sbumpc();
  while (c != std::char_traits<char>::eof() && is_space(c)) c = in_.sbumpc();
  if (c == std::char_traits<char>::eof()) return -1;
  if (c >= '0' && c <= '9') return c - '0';
  if (c >= 'a' && c <= 'f') return c - 'a' + 10;
  if (c >= 'A' && c <= 'F') return c - 'A' + 10;
  const char text[2] = {static_cast<char>(c), '\0'};
  throw Error(fmt::format("{}: hex data has '{}' at byte {} of the voxels, not a hexadecimal digit",
                          what_, shown(text), index_));
}

void HexBytes::read(std::span<uint8_t> out, uint64_t expected) {
  for (uint8_t& byte : out) {
    const int high = next_digit();
    const int low = high < 0 ? -1 : next_digit();
    if (low < 0)
      throw Error(fmt::format("{}: the hex data ends after {} bytes; the header gives {}", what_,
                              index_, expected));
    byte = static_cast<uint8_t>(high * 16 + low);
    ++index_;
  }
}

void HexBytes::skip(uint64_t count, uint64_t expected) {
  uint8_t scratch[256];
  while (count > 0) {
    const size_t n = static_cast<size_t>(std::min<uint64_t>(count, sizeof scratch));
    read(std::span<uint8_t>(scratch, n), expected);
    count -= n;
  }
}

void HexBytes::expect_end(uint64_t expected) {
  if (next_digit() >= 0)
    throw Error(fmt::format("{}: the hex data holds more than the {} bytes the header gives", what_,
                            expected));
}

}  // namespace imx::detail
