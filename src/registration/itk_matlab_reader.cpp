// ITK's binary transform files (.mat, MatlabTransformIO; ANTs writes its affines this way):
// MATLAB v4 variables, each a 20-byte header (type, rows, columns, imaginary flag, name
// length), the name with its NUL, then the values column by column.
#include <bit>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <optional>

#include <fmt/format.h>

#include "intermix/error.hpp"
#include "registration/transform_readers.hpp"

namespace imx::detail {
namespace {

constexpr size_t kHeaderBytes = 20;
constexpr int32_t kMaxValues = 4096;  // an ITK linear transform has at most a few dozen
constexpr int32_t kMaxName = 256;

int32_t int_at(std::string_view bytes, size_t at, bool big_endian) {
  uint32_t v = 0;
  std::memcpy(&v, bytes.data() + at, 4);
  if (big_endian != (std::endian::native == std::endian::big)) v = __builtin_bswap32(v);
  return static_cast<int32_t>(v);
}

// The byte order of a v4 header at `at` by its type field (MOPT: M = 0 little, 1 big endian;
// O = 0; P = 0 double, 1 single; T = 0 numeric), nullopt when neither order reads as one.
std::optional<bool> header_order(std::string_view bytes, size_t at) {
  if (bytes.size() < at + kHeaderBytes) return std::nullopt;
  for (bool big : {false, true}) {
    const int32_t type = int_at(bytes, at, big);
    if (type == (big ? 1000 : 0) || type == (big ? 1010 : 10)) return big;
  }
  return std::nullopt;
}

struct Variable {
  std::string name;
  std::vector<double> values;
};

Variable read_variable(std::string_view bytes, size_t& at, const std::string& what,
                       const char* expected) {
  if (bytes.size() - at < kHeaderBytes)
    throw Error(fmt::format("{}: truncated: {} bytes at byte {}, where the header of {} needs {}",
                            what, bytes.size() - at, at, expected, kHeaderBytes));
  const std::optional<bool> big = header_order(bytes, at);
  if (!big)
    throw Error(
        fmt::format("{}: byte {}: not a MATLAB v4 numeric variable of doubles or singles "
                    "(only ITK's MatlabTransformIO layout is read; other .mat files are "
                    "not transforms intermix knows)",
                    what, at));
  const bool single = int_at(bytes, at, *big) % 100 == 10;
  const int32_t rows = int_at(bytes, at + 4, *big), cols = int_at(bytes, at + 8, *big);
  const int32_t imag = int_at(bytes, at + 12, *big), name_length = int_at(bytes, at + 16, *big);
  if (cols != 1 || rows < 0 || rows > kMaxValues)
    throw Error(
        fmt::format("{}: byte {}: a {} x {} matrix; ITK's transform files hold column "
                    "vectors of at most {} values",
                    what, at, rows, cols, kMaxValues));
  if (imag != 0) throw Error(fmt::format("{}: byte {}: a complex variable", what, at));
  if (name_length < 1 || name_length > kMaxName)
    throw Error(fmt::format("{}: byte {}: name length {} is not in [1, {}]", what, at, name_length,
                            kMaxName));
  at += kHeaderBytes;
  const size_t value_bytes = static_cast<size_t>(rows) * (single ? 4 : 8);
  if (bytes.size() - at < static_cast<size_t>(name_length) + value_bytes)
    throw Error(fmt::format("{}: truncated: the variable at byte {} needs {} bytes, {} remain",
                            what, at - kHeaderBytes, name_length + value_bytes, bytes.size() - at));
  Variable v;
  v.name.assign(bytes.data() + at, static_cast<size_t>(name_length));
  if (v.name.back() != '\0')
    throw Error(fmt::format("{}: byte {}: the variable's name does not end in NUL", what, at));
  v.name.pop_back();
  at += static_cast<size_t>(name_length);
  for (int32_t i = 0; i < rows; ++i) {
    double value = 0.0;
    if (single) {
      uint32_t u = 0;
      std::memcpy(&u, bytes.data() + at, 4);
      if (*big != (std::endian::native == std::endian::big)) u = __builtin_bswap32(u);
      value = std::bit_cast<float>(u);
      at += 4;
    } else {
      uint64_t u = 0;
      std::memcpy(&u, bytes.data() + at, 8);
      if (*big != (std::endian::native == std::endian::big)) u = __builtin_bswap64(u);
      value = std::bit_cast<double>(u);
      at += 8;
    }
    if (!std::isfinite(value))
      throw Error(
          fmt::format("{}: variable '{}' value {} is not a finite number (NaN or "
                      "infinity)",
                      what, v.name.substr(0, 80), i));
    v.values.push_back(value);
  }
  return v;
}

}  // namespace

bool looks_like_matlab_v4(std::string_view bytes) {
  const std::optional<bool> big = header_order(bytes, 0);
  if (!big) return false;
  const int32_t imag = int_at(bytes, 12, *big), name_length = int_at(bytes, 16, *big);
  return (imag == 0 || imag == 1) && name_length >= 1 && name_length <= kMaxName;
}

glm::dmat4 read_itk_matlab(std::string_view bytes, const std::string& what) {
  if (bytes.substr(0, 10) == "MATLAB 5.0" || bytes.substr(0, 10) == "MATLAB 7.3")
    throw Error(
        fmt::format("{}: a MATLAB 5/7 file; ITK writes transforms as MATLAB v4 "
                    "variables (other .mat layouts are not read)",
                    what));
  size_t at = 0;
  Variable parameters = read_variable(bytes, at, what, "the parameters");
  if (at == bytes.size())
    throw Error(
        fmt::format("{}: truncated: the fixed parameters (\"fixed\") are missing after "
                    "'{}'",
                    what, parameters.name.substr(0, 80)));
  Variable fixed = read_variable(bytes, at, what, "the fixed parameters (\"fixed\")");
  if (fixed.name != "fixed")
    throw Error(
        fmt::format("{}: the second variable is '{}'; ITK names its fixed parameters "
                    "\"fixed\"",
                    what, fixed.name.substr(0, 80)));
  if (at != bytes.size())
    throw Error(
        fmt::format("{}: more than one transform ({} bytes follow the first); one is "
                    "read",
                    what, bytes.size() - at));
  return itk_fixed_to_moving({parameters.name, parameters.values, fixed.values}, what);
}

}  // namespace imx::detail
