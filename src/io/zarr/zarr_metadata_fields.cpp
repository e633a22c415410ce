#include "io/zarr/zarr_metadata_fields.hpp"

#include <algorithm>
#include <cstring>
#include <limits>

#include <fmt/format.h>

#include "intermix/limits.hpp"
#include "io/streams/json_depth.hpp"

namespace imx::detail {

namespace {

using nlohmann::json;

constexpr size_t kMaxDimensions = 32;

template <class T>
void put(std::vector<uint8_t>& bytes, T value) {
  bytes.resize(sizeof(T));
  std::memcpy(bytes.data(), &value, sizeof(T));
}

// v3's "0x7fc00000": the float's bits, most significant first.
bool hex_bits(const std::string& s, size_t size, std::vector<uint8_t>& fill) {
  if (s.size() != 2 + 2 * size || s[0] != '0' || s[1] != 'x') return false;
  uint64_t bits = 0;
  for (size_t k = 2; k < s.size(); ++k) {
    const char c = s[k];
    const int digit = c >= '0' && c <= '9'   ? c - '0'
                      : c >= 'a' && c <= 'f' ? c - 'a' + 10
                      : c >= 'A' && c <= 'F' ? c - 'A' + 10
                                             : -1;
    if (digit < 0) return false;
    bits = bits << 4 | static_cast<uint64_t>(digit);
  }
  if (size == 4)
    put(fill, static_cast<uint32_t>(bits));
  else
    put(fill, bits);
  return true;
}

}  // namespace

Error zarr_bad_field(const std::string& what, std::string_view field, const json& value,
                     std::string_view why) {
  std::string shown = value.dump();
  if (shown.size() > 80) shown = shown.substr(0, 77) + "...";
  return Error(fmt::format("{}: field '{}' {} {}", what, field, shown, why));
}

std::vector<int64_t> zarr_sizes(const json& v, std::string_view field, const std::string& what,
                                int64_t smallest) {
  if (!v.is_array() || v.empty() || v.size() > kMaxDimensions)
    throw zarr_bad_field(what, field, v,
                         fmt::format("must be a list of 1 to {} integers", kMaxDimensions));
  std::vector<int64_t> out;
  for (const json& n : v) {
    if (!n.is_number_integer()) throw zarr_bad_field(what, field, v, "must hold integers");
    const int64_t value = n.get<int64_t>();
    if (value < smallest || (n.is_number_unsigned() && n.get<uint64_t>() > INT64_MAX))
      throw zarr_bad_field(what, field, v, fmt::format("must hold integers >= {}", smallest));
    if (value > std::numeric_limits<int>::max())
      throw zarr_bad_field(what, field, v, "holds a size beyond 2^31 - 1");
    out.push_back(value);
  }
  return out;
}

json parse_zarr_json(std::string_view text, const std::string& what) {
  if (json_nested_deeper_than(text, kMaxZarrJsonDepth))
    throw Error(fmt::format("{}: JSON nested deeper than {} levels", what, kMaxZarrJsonDepth));
  json doc = json::parse(text, nullptr, false);
  if (doc.is_discarded()) throw Error(fmt::format("{}: not JSON (Zarr metadata is JSON)", what));
  if (!doc.is_object()) throw Error(fmt::format("{}: not a JSON object", what));
  return doc;
}

void set_zarr_fill(const json& v, ZarrArray& a, bool hex_floats) {
  const size_t size = raw_type_size(a.type);
  a.fill.assign(size, 0);
  // null: zeros (zarr leaves such elements uninitialised; zero is what its writers mean).
  if (v.is_null()) return;
  const bool is_float = a.type == RawType::f32 || a.type == RawType::f64;
  double value = 0;
  if (v.is_string() && is_float) {
    const std::string s = v.get<std::string>();
    if (s == "NaN")
      value = std::numeric_limits<double>::quiet_NaN();
    else if (s == "Infinity")
      value = std::numeric_limits<double>::infinity();
    else if (s == "-Infinity")
      value = -std::numeric_limits<double>::infinity();
    else if (hex_floats && hex_bits(s, size, a.fill)) {
      if (a.big_endian) std::reverse(a.fill.begin(), a.fill.end());
      return;
    } else
      throw zarr_bad_field(a.what, "fill_value", v,
                           hex_floats ? "is not a number, \"NaN\", \"Infinity\", \"-Infinity\" "
                                        "or \"0x\" and the float's bits in hex"
                                      : "is not a number, \"NaN\" or \"Infinity\"");
  } else if (v.is_number_float() && is_float) {
    value = v.get<double>();
  } else if (v.is_number_integer()) {
    value = v.is_number_unsigned() ? static_cast<double>(v.get<uint64_t>())
                                   : static_cast<double>(v.get<int64_t>());
  } else if (v.is_boolean()) {
    value = v.get<bool>() ? 1 : 0;
  } else {
    throw zarr_bad_field(a.what, "fill_value", v,
                         fmt::format("does not fit dtype {}", raw_type_name(a.type)));
  }
  const auto integer = [&](double lo, double hi) {
    if (!(value >= lo && value <= hi))
      throw zarr_bad_field(a.what, "fill_value", v,
                           fmt::format("does not fit dtype {}", raw_type_name(a.type)));
  };
  switch (a.type) {
    case RawType::i8:
      integer(-128, 127), put(a.fill, static_cast<int8_t>(value));
      break;
    case RawType::u8:
      integer(0, 255), put(a.fill, static_cast<uint8_t>(value));
      break;
    case RawType::i16:
      integer(-32768, 32767), put(a.fill, static_cast<int16_t>(value));
      break;
    case RawType::u16:
      integer(0, 65535), put(a.fill, static_cast<uint16_t>(value));
      break;
    case RawType::i32:
      integer(INT32_MIN, INT32_MAX), put(a.fill, static_cast<int32_t>(value));
      break;
    case RawType::u32:
      integer(0, UINT32_MAX), put(a.fill, static_cast<uint32_t>(value));
      break;
    // 64-bit fill values beyond 2^53 lose precision through double; they become f32 anyway.
    case RawType::i64:
      if (v.is_number_integer() && !v.is_number_unsigned())
        put(a.fill, v.get<int64_t>());
      else
        integer(0, 9.2e18), put(a.fill, static_cast<int64_t>(value));
      break;
    case RawType::u64:
      if (v.is_number_unsigned())
        put(a.fill, v.get<uint64_t>());
      else
        integer(0, 0), put(a.fill, uint64_t{0});
      break;
    case RawType::f32:
      put(a.fill, static_cast<float>(value));
      break;
    case RawType::f64:
      put(a.fill, value);
      break;
  }
  if (a.big_endian) std::reverse(a.fill.begin(), a.fill.end());
}

void set_zarr_chunk_bytes(ZarrArray& a, std::string_view field, const json& value) {
  uint64_t elements = 1;
  for (int64_t n : a.chunks) {
    elements *= static_cast<uint64_t>(n);
    if (elements > kMaxVoxels)
      throw zarr_bad_field(a.what, field, value,
                           fmt::format("gives chunks of more than {} elements", kMaxVoxels));
  }
  a.chunk_bytes = static_cast<size_t>(elements) * raw_type_size(a.type);
  check_memory(a.chunk_bytes, a.what + " (one chunk)");
}

}  // namespace imx::detail
