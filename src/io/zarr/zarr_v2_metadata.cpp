// Zarr v2 array metadata (.zarray): declared in zarr_array.hpp.
#include <algorithm>
#include <iterator>

#include <fmt/format.h>

#include "io/zarr/zarr_array.hpp"
#include "io/zarr/zarr_metadata_fields.hpp"

namespace imx::detail {

namespace {

using nlohmann::json;

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
    return zarr_bad_field(a.what, "dtype", v,
                          "is not supported (supported: u1 i1 u2 i2 u4 i4 u8 i8 f4 f8, with byte "
                          "order '<', '>' or '|')");
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

void parse_compressor(const json& doc, ZarrArray& a) {
  const json v = doc.contains("compressor") ? doc["compressor"] : json();
  if (v.is_null()) return;
  if (!v.is_object() || !v.contains("id") || !v["id"].is_string())
    throw zarr_bad_field(a.what, "compressor", v, "must be null or an object with an 'id'");
  const std::string id = v["id"].get<std::string>();
  for (ZarrCompressor c :
       {ZarrCompressor::zlib, ZarrCompressor::gzip, ZarrCompressor::blosc, ZarrCompressor::zstd})
    if (id == zarr_compressor_name(c)) {
      a.codecs.compressor = c;
      return;
    }
  throw zarr_bad_field(a.what, "compressor", v,
                       fmt::format("names '{}', which is not supported (supported: null, zlib, "
                                   "gzip, blosc, zstd)",
                                   id));
}

}  // namespace

ZarrArray parse_zarray(std::string_view text, const std::filesystem::path& dir,
                       const std::string& what) {
  ZarrArray a;
  a.dir = dir;
  a.what = what;
  const json doc = parse_zarr_json(text, what);
  if (!doc.contains("zarr_format") || doc["zarr_format"] != 2)
    throw zarr_bad_field(what, "zarr_format",
                         doc.contains("zarr_format") ? doc["zarr_format"] : json(),
                         "is not supported (only Zarr v2; v3 arrays have zarr.json)");
  if (!doc.contains("shape")) throw Error(fmt::format("{}: missing field 'shape'", what));
  a.shape = zarr_sizes(doc["shape"], "shape", what, 1);
  // A lying shape: checked before anything is sized by it.
  uint64_t total = 1;
  for (int64_t n : a.shape)
    if (__builtin_mul_overflow(total, static_cast<uint64_t>(n), &total))
      throw zarr_bad_field(what, "shape", doc["shape"], "has more elements than 2^64");
  if (!doc.contains("chunks")) throw Error(fmt::format("{}: missing field 'chunks'", what));
  a.chunks = zarr_sizes(doc["chunks"], "chunks", what, 1);
  if (a.chunks.size() != a.shape.size())
    throw zarr_bad_field(
        what, "chunks", doc["chunks"],
        fmt::format("has {} sizes, 'shape' has {}", a.chunks.size(), a.shape.size()));
  parse_dtype(doc, a);
  const json order = doc.contains("order") ? doc["order"] : json();
  if (order != "C")
    throw zarr_bad_field(what, "order", order,
                         order == "F" ? "is not supported (Fortran order; only \"C\")"
                                      : "is not supported (only \"C\")");
  set_zarr_fill(doc.contains("fill_value") ? doc["fill_value"] : json(), a, false);
  parse_compressor(doc, a);
  if (doc.contains("filters") && !doc["filters"].is_null() &&
      !(doc["filters"].is_array() && doc["filters"].empty())) {
    const json& f = doc["filters"];
    const std::string id =
        f.is_array() && f[0].is_object() && f[0].contains("id") ? f[0]["id"].dump() : f.dump();
    throw zarr_bad_field(what, "filters", f,
                         fmt::format("names {}: filters are not supported (only null)", id));
  }
  // null (as older zarr writes it) is the default ".".
  if (doc.contains("dimension_separator") && !doc["dimension_separator"].is_null()) {
    const json& s = doc["dimension_separator"];
    if (s != "." && s != "/")
      throw zarr_bad_field(what, "dimension_separator", s,
                           "is not supported (only \".\" or \"/\")");
    a.separator = s.get<std::string>()[0];
  }
  set_zarr_chunk_bytes(a, "chunks", doc["chunks"]);
  return a;
}

ZarrArray read_zarray(const std::filesystem::path& dir) {
  const std::filesystem::path file = dir / ".zarray";
  return parse_zarray(read_zarr_metadata(file, kMaxZarrMetadataBytes), dir, file.string());
}

}  // namespace imx::detail
