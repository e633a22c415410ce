#include "io/zarr/zarr_array.hpp"

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstring>
#include <fstream>
#include <limits>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "intermix/error.hpp"
#include "intermix/limits.hpp"
#include "io/streams/json_depth.hpp"

namespace imx::detail {

namespace {

using nlohmann::json;

// .zarray and .zattrs are small documents; more is not metadata.
constexpr uintmax_t kMaxMetadataBytes = 1 << 20;
constexpr int kMaxJsonDepth = 32;
constexpr size_t kMaxDimensions = 32;
// Chunk files one volume may span: each is a file to open, so tiny chunks of a large grid would
// take hours (a 2048^3 grid in 64^3 chunks has 32768).
constexpr uint64_t kMaxChunksPerGrid = uint64_t{1} << 20;

Error bad_field(const std::string& what, std::string_view field, const json& value,
                std::string_view why) {
  std::string shown = value.dump();
  if (shown.size() > 80) shown = shown.substr(0, 77) + "...";
  return Error(fmt::format("{}: field '{}' {} {}", what, field, shown, why));
}

std::vector<int64_t> parse_sizes(const json& doc, const char* field, const std::string& what,
                                 int64_t smallest) {
  if (!doc.contains(field)) throw Error(fmt::format("{}: missing field '{}'", what, field));
  const json& v = doc[field];
  if (!v.is_array() || v.empty() || v.size() > kMaxDimensions)
    throw bad_field(what, field, v,
                    fmt::format("must be a list of 1 to {} integers", kMaxDimensions));
  std::vector<int64_t> out;
  for (const json& n : v) {
    if (!n.is_number_integer()) throw bad_field(what, field, v, "must hold integers");
    const int64_t value = n.get<int64_t>();
    if (value < smallest || (n.is_number_unsigned() && n.get<uint64_t>() > INT64_MAX))
      throw bad_field(what, field, v, fmt::format("must hold integers >= {}", smallest));
    if (value > std::numeric_limits<int>::max())
      throw bad_field(what, field, v, "holds a size beyond 2^31 - 1");
    out.push_back(value);
  }
  return out;
}

struct DtypeName {
  std::string_view text;
  RawType type;
};

void parse_dtype(const json& doc, ZarrArray& a) {
  static constexpr DtypeName names[] = {
      {"u1", RawType::u8},  {"i1", RawType::i8},  {"u2", RawType::u16}, {"i2", RawType::i16},
      {"u4", RawType::u32}, {"i4", RawType::i32}, {"u8", RawType::u64}, {"i8", RawType::i64},
      {"f4", RawType::f32}, {"f8", RawType::f64}};
  if (!doc.contains("dtype")) throw Error(fmt::format("{}: missing field 'dtype'", a.what));
  const json& v = doc["dtype"];
  const std::string text = v.is_string() ? v.get<std::string>() : std::string();
  const auto unsupported = [&] {
    return bad_field(a.what, "dtype", v,
                     "is not supported (supported: u1 i1 u2 i2 u4 i4 u8 i8 f4 f8, with byte order "
                     "'<', '>' or '|')");
  };
  if (text.size() != 3 || (text[0] != '<' && text[0] != '>' && text[0] != '|')) throw unsupported();
  const std::string_view kind = std::string_view(text).substr(1);
  const auto it = std::find_if(std::begin(names), std::end(names),
                               [&](const DtypeName& n) { return n.text == kind; });
  if (it == std::end(names)) throw unsupported();
  a.type = it->type;
  // '|' (no byte order) is numpy's mark for one-byte types only.
  if (text[0] == '|' && raw_type_size(a.type) != 1) throw unsupported();
  a.big_endian = text[0] == '>' && raw_type_size(a.type) > 1;
}

template <class T>
void put(std::vector<uint8_t>& bytes, T value) {
  bytes.resize(sizeof(T));
  std::memcpy(bytes.data(), &value, sizeof(T));
}

// The fill value as one element in the array's byte order. null: zeros (zarr leaves such
// elements uninitialised; zero is what its writers mean).
void parse_fill(const json& doc, ZarrArray& a) {
  const json v = doc.contains("fill_value") ? doc["fill_value"] : json();
  const size_t size = raw_type_size(a.type);
  a.fill.assign(size, 0);
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
    else
      throw bad_field(a.what, "fill_value", v, "is not a number, \"NaN\" or \"Infinity\"");
  } else if (v.is_number_float() && is_float) {
    value = v.get<double>();
  } else if (v.is_number_integer()) {
    value = v.is_number_unsigned() ? static_cast<double>(v.get<uint64_t>())
                                   : static_cast<double>(v.get<int64_t>());
  } else if (v.is_boolean()) {
    value = v.get<bool>() ? 1 : 0;
  } else {
    throw bad_field(a.what, "fill_value", v,
                    fmt::format("does not fit dtype {}", raw_type_name(a.type)));
  }
  const auto integer = [&](double lo, double hi) {
    if (!(value >= lo && value <= hi))
      throw bad_field(a.what, "fill_value", v,
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

void parse_compressor(const json& doc, ZarrArray& a) {
  const json v = doc.contains("compressor") ? doc["compressor"] : json();
  if (v.is_null()) return;
  if (!v.is_object() || !v.contains("id") || !v["id"].is_string())
    throw bad_field(a.what, "compressor", v, "must be null or an object with an 'id'");
  const std::string id = v["id"].get<std::string>();
  for (ZarrCompressor c :
       {ZarrCompressor::zlib, ZarrCompressor::gzip, ZarrCompressor::blosc, ZarrCompressor::zstd})
    if (id == zarr_compressor_name(c)) {
      a.compressor = c;
      return;
    }
  throw bad_field(a.what, "compressor", v,
                  fmt::format("names '{}', which is not supported (supported: null, zlib, gzip, "
                              "blosc, zstd)",
                              id));
}

}  // namespace

std::filesystem::path ZarrArray::chunk_file(std::span<const int64_t> index) const {
  std::string key;
  for (size_t d = 0; d < index.size(); ++d) {
    if (d) key += separator;
    key += std::to_string(index[d]);
  }
  return dir / key;
}

ZarrArray parse_zarray(std::string_view text, const std::filesystem::path& dir,
                       const std::string& what) {
  ZarrArray a;
  a.dir = dir;
  a.what = what;
  if (json_nested_deeper_than(text, kMaxJsonDepth))
    throw Error(fmt::format("{}: JSON nested deeper than {} levels", what, kMaxJsonDepth));
  json doc = json::parse(text, nullptr, false);
  if (doc.is_discarded()) throw Error(fmt::format("{}: not JSON (a .zarray must be JSON)", what));
  if (!doc.is_object()) throw Error(fmt::format("{}: not a JSON object", what));
  if (!doc.contains("zarr_format") || doc["zarr_format"] != 2)
    throw bad_field(what, "zarr_format", doc.contains("zarr_format") ? doc["zarr_format"] : json(),
                    "is not supported (only Zarr v2; v3 arrays have zarr.json)");
  a.shape = parse_sizes(doc, "shape", what, 1);
  // A lying shape: checked before anything is sized by it.
  uint64_t total = 1;
  for (int64_t n : a.shape)
    if (__builtin_mul_overflow(total, static_cast<uint64_t>(n), &total))
      throw bad_field(what, "shape", doc["shape"], "has more elements than 2^64");
  a.chunks = parse_sizes(doc, "chunks", what, 1);
  if (a.chunks.size() != a.shape.size())
    throw bad_field(what, "chunks", doc["chunks"],
                    fmt::format("has {} sizes, 'shape' has {}", a.chunks.size(), a.shape.size()));
  parse_dtype(doc, a);
  const json order = doc.contains("order") ? doc["order"] : json();
  if (order != "C")
    throw bad_field(what, "order", order,
                    order == "F" ? "is not supported (Fortran order; only \"C\")"
                                 : "is not supported (only \"C\")");
  parse_fill(doc, a);
  parse_compressor(doc, a);
  if (doc.contains("filters") && !doc["filters"].is_null() &&
      !(doc["filters"].is_array() && doc["filters"].empty())) {
    const json& f = doc["filters"];
    const std::string id =
        f.is_array() && f[0].is_object() && f[0].contains("id") ? f[0]["id"].dump() : f.dump();
    throw bad_field(what, "filters", f,
                    fmt::format("names {}: filters are not supported (only null)", id));
  }
  // null (as older zarr writes it) is the default ".".
  if (doc.contains("dimension_separator") && !doc["dimension_separator"].is_null()) {
    const json& s = doc["dimension_separator"];
    if (s != "." && s != "/")
      throw bad_field(what, "dimension_separator", s, "is not supported (only \".\" or \"/\")");
    a.separator = s.get<std::string>()[0];
  }
  uint64_t elements = 1;
  for (int64_t n : a.chunks) {
    elements *= static_cast<uint64_t>(n);
    if (elements > kMaxVoxels)
      throw bad_field(what, "chunks", doc["chunks"],
                      fmt::format("gives chunks of more than {} elements", kMaxVoxels));
  }
  a.chunk_bytes = static_cast<size_t>(elements) * raw_type_size(a.type);
  check_memory(a.chunk_bytes, what + " (one chunk)");
  return a;
}

std::string read_zarr_metadata(const std::filesystem::path& file, uintmax_t max_bytes) {
  const std::string what = file.string();
  std::error_code ec;
  const uintmax_t size = std::filesystem::file_size(file, ec);
  if (ec) throw FileError(fmt::format("{}: cannot read: {}", what, ec.message()), ec.value());
  if (size > max_bytes)
    throw Error(
        fmt::format("{}: {} bytes, more than {} (not Zarr metadata)", what, size, max_bytes));
  std::ifstream in(file, std::ios::binary);
  if (!in) throw FileError(fmt::format("{}: cannot open file", what), errno);
  std::string text(static_cast<size_t>(size), '\0');
  in.read(text.data(), static_cast<std::streamsize>(size));
  if (static_cast<uintmax_t>(in.gcount()) != size)
    throw Error(fmt::format("{}: could not read the whole file", what));
  return text;
}

ZarrArray read_zarray(const std::filesystem::path& dir) {
  const std::filesystem::path file = dir / ".zarray";
  return parse_zarray(read_zarr_metadata(file, kMaxMetadataBytes), dir, file.string());
}

void decode_zarr_chunk(const ZarrArray& array, std::span<const uint8_t> stored,
                       std::span<uint8_t> out, const std::string& what) {
  if (out.size() != array.chunk_bytes)
    throw Error(fmt::format("{}: internal: chunk buffer of {} bytes, expected {}", what, out.size(),
                            array.chunk_bytes));
  decode_zarr_chunk(array.compressor, stored, out, what);
}

void read_zarr_chunk(const ZarrArray& array, std::span<const int64_t> index,
                     std::span<uint8_t> out) {
  const std::filesystem::path file = array.chunk_file(index);
  const std::string what = file.string();
  std::error_code ec;
  const auto status = std::filesystem::status(file, ec);
  if (status.type() == std::filesystem::file_type::not_found) {
    // A chunk zarr never wrote holds the fill value everywhere.
    const size_t n = array.fill.size();
    for (size_t i = 0; i + n <= out.size(); i += n)
      std::memcpy(out.data() + i, array.fill.data(), n);
    return;
  }
  if (ec || status.type() != std::filesystem::file_type::regular)
    throw Error(fmt::format("{}: chunk is not a readable file", what));
  const uintmax_t size = std::filesystem::file_size(file, ec);
  if (ec) throw FileError(fmt::format("{}: cannot read: {}", what, ec.message()), ec.value());
  // No codec here expands data by more than a few percent and a block header.
  const uintmax_t most = array.chunk_bytes + array.chunk_bytes / 8 + 65536;
  if (size > most)
    throw Error(fmt::format("{}: chunk file of {} bytes, more than any {} encoding of its {} bytes",
                            what, size, zarr_compressor_name(array.compressor), array.chunk_bytes));
  std::vector<uint8_t> stored(static_cast<size_t>(size));
  std::ifstream in(file, std::ios::binary);
  if (!in) throw FileError(fmt::format("{}: cannot open chunk file", what), errno);
  in.read(reinterpret_cast<char*>(stored.data()), static_cast<std::streamsize>(size));
  if (static_cast<uintmax_t>(in.gcount()) != size)
    throw Error(fmt::format("{}: could not read the whole chunk file", what));
  decode_zarr_chunk(array, stored, out, what);
}

void read_zarr_block(const ZarrArray& array, std::span<const int64_t> lead,
                     std::span<uint8_t> out) {
  const size_t n = array.shape.size();
  if (n < 3 || lead.size() != n - 3)
    throw Error(fmt::format("{}: internal: {} leading indices for {} dimensions", array.what,
                            lead.size(), n));
  const size_t item = raw_type_size(array.type);
  const int64_t X = array.shape[n - 1], Y = array.shape[n - 2], Z = array.shape[n - 3];
  if (out.size() != static_cast<size_t>(X) * Y * Z * item)
    throw Error(fmt::format("{}: internal: block buffer of {} bytes", array.what, out.size()));
  // Element strides of one chunk, C order.
  std::vector<size_t> stride(n, 1);
  for (size_t d = n - 1; d > 0; --d)
    stride[d - 1] = stride[d] * static_cast<size_t>(array.chunks[d]);
  std::vector<int64_t> index(n);
  size_t lead_offset = 0;
  for (size_t d = 0; d + 3 < n; ++d) {
    index[d] = lead[d] / array.chunks[d];
    lead_offset += static_cast<size_t>(lead[d] % array.chunks[d]) * stride[d];
  }
  const int64_t cx = array.chunks[n - 1], cy = array.chunks[n - 2], cz = array.chunks[n - 3];
  const uint64_t grid_chunks = static_cast<uint64_t>((X + cx - 1) / cx) * ((Y + cy - 1) / cy) *
                               static_cast<uint64_t>((Z + cz - 1) / cz);
  if (grid_chunks > kMaxChunksPerGrid)
    throw Error(
        fmt::format("{}: field 'chunks': a {}x{}x{} grid in chunks of {}x{}x{} is {} chunk "
                    "files, more than {}",
                    array.what, X, Y, Z, cx, cy, cz, grid_chunks, kMaxChunksPerGrid));
  std::vector<uint8_t> chunk(array.chunk_bytes);
  for (int64_t kz = 0; kz * cz < Z; ++kz)
    for (int64_t ky = 0; ky * cy < Y; ++ky)
      for (int64_t kx = 0; kx * cx < X; ++kx) {
        index[n - 3] = kz, index[n - 2] = ky, index[n - 1] = kx;
        read_zarr_chunk(array, index, chunk);
        // Edge chunks are stored full-size: only the part inside the shape is copied.
        const int64_t z0 = kz * cz, y0 = ky * cy, x0 = kx * cx;
        const int64_t nz = std::min(cz, Z - z0), ny = std::min(cy, Y - y0),
                      nx = std::min(cx, X - x0);
        for (int64_t z = 0; z < nz; ++z)
          for (int64_t y = 0; y < ny; ++y) {
            const size_t src = lead_offset + static_cast<size_t>(z) * stride[n - 3] +
                               static_cast<size_t>(y) * stride[n - 2];
            const size_t dst = (static_cast<size_t>(z0 + z) * Y + (y0 + y)) * X + x0;
            std::memcpy(out.data() + dst * item, chunk.data() + src * item,
                        static_cast<size_t>(nx) * item);
          }
      }
}

}  // namespace imx::detail
