// Zarr v3 array metadata (zarr.json, node_type "array"): declared in zarr_array.hpp.
#include <algorithm>
#include <iterator>

#include <fmt/format.h>

#include "io/zarr/zarr_array.hpp"
#include "io/zarr/zarr_metadata_fields.hpp"

namespace imx::detail {

namespace {

using nlohmann::json;

// Inner chunks one shard may hold: its index is read whole (16 bytes each).
constexpr uint64_t kMaxInnerChunks = uint64_t{1} << 20;

// An extension point's entry: a name alone, or {"name", "configuration", "must_understand"}.
struct Named {
  std::string name;
  json configuration = json::object();
};

Named named(const json& v, std::string_view field, const std::string& what) {
  if (v.is_string()) return {v.get<std::string>()};
  if (!v.is_object() || !v.contains("name") || !v["name"].is_string())
    throw zarr_bad_field(what, field, v, "must be a name or an object with a 'name'");
  Named n{v["name"].get<std::string>()};
  if (v.contains("configuration")) {
    if (!v["configuration"].is_object())
      throw zarr_bad_field(what, field, v, "has a 'configuration' that is not an object");
    n.configuration = v["configuration"];
  }
  return n;
}

void parse_data_type(const json& doc, ZarrArray& a) {
  static constexpr std::pair<std::string_view, RawType> names[] = {
      {"int8", RawType::i8},    {"uint8", RawType::u8},   {"int16", RawType::i16},
      {"uint16", RawType::u16}, {"int32", RawType::i32},  {"uint32", RawType::u32},
      {"int64", RawType::i64},  {"uint64", RawType::u64}, {"float32", RawType::f32},
      {"float64", RawType::f64}};
  if (!doc.contains("data_type")) throw Error(fmt::format("{}: missing field 'data_type'", a.what));
  const Named t = named(doc["data_type"], "data_type", a.what);
  const auto it = std::find_if(std::begin(names), std::end(names),
                               [&](const auto& n) { return n.first == t.name; });
  if (it == std::end(names))
    throw zarr_bad_field(a.what, "data_type", doc["data_type"],
                         "is not supported (supported: int8 uint8 int16 uint16 int32 uint32 int64 "
                         "uint64 float32 float64)");
  a.type = it->second;
}

void parse_key_encoding(const json& doc, ZarrArray& a) {
  if (!doc.contains("chunk_key_encoding"))
    throw Error(fmt::format("{}: missing field 'chunk_key_encoding'", a.what));
  const json& v = doc["chunk_key_encoding"];
  const Named e = named(v, "chunk_key_encoding", a.what);
  if (e.name != "default" && e.name != "v2")
    throw zarr_bad_field(a.what, "chunk_key_encoding", v,
                         "is not supported (only \"default\" and \"v2\")");
  // "c" (default) or none (v2); assign(n, c): GCC 12 warns (-Wrestrict) on assigning a literal.
  a.key_prefix.assign(e.name == "default" ? 1 : 0, 'c');
  a.separator = e.name == "default" ? '/' : '.';
  if (e.configuration.contains("separator")) {
    const json& s = e.configuration["separator"];
    if (s != "." && s != "/")
      throw zarr_bad_field(a.what, "chunk_key_encoding", v,
                           "has a separator other than \".\" or \"/\"");
    a.separator = s.get<std::string>()[0];
  }
}

// The codecs of one chunk: array-to-array (transpose), one array-to-bytes (bytes or, when
// `outer`, sharding_indexed), then bytes-to-bytes (gzip, zstd, blosc, crc32c).
struct Chain {
  ZarrCodecChain codecs;
  bool big_endian = false;
  const json* sharding = nullptr;  // the sharding_indexed configuration
};

Chain parse_chain(const json& list, const std::string& field, const ZarrArray& a, bool outer) {
  if (!list.is_array() || list.empty())
    throw zarr_bad_field(a.what, field, list, "must be a non-empty list of codecs");
  Chain c;
  enum { arrays, bytes, after } stage = arrays;
  const size_t n = a.shape.size();
  for (const json& entry : list) {
    const Named codec = named(entry, field, a.what);
    const json& config = codec.configuration;
    const auto refuse = [&](std::string_view why) {
      return zarr_bad_field(a.what, field, entry, fmt::format("codec '{}' {}", codec.name, why));
    };
    if (codec.name == "transpose") {
      if (stage != arrays) throw refuse("comes after the array's bytes codec");
      const json order = config.value("order", json());
      std::vector<int> perm;
      if (order.is_array() && order.size() == n)
        for (const json& o : order)
          if (o.is_number_integer() && o.get<int64_t>() >= 0 && o.get<int64_t>() < int64_t(n))
            perm.push_back(o.get<int>());
      std::vector<int> sorted = perm;
      std::sort(sorted.begin(), sorted.end());
      if (perm.size() != n || std::adjacent_find(sorted.begin(), sorted.end()) != sorted.end())
        throw refuse(fmt::format("needs an 'order' permuting the {} axes", n));
      if (!c.codecs.order.empty()) throw refuse("is given twice (only one transpose is read)");
      c.codecs.order = perm;
    } else if (codec.name == "bytes" || (outer && codec.name == "sharding_indexed")) {
      if (stage != arrays) throw refuse("is a second array-to-bytes codec");
      stage = bytes;
      if (codec.name == "sharding_indexed") {
        if (!entry.is_object() || !entry.contains("configuration"))
          throw refuse("needs a 'configuration'");
        c.sharding = &entry["configuration"];
        continue;
      }
      const json endian = config.value("endian", json());
      if (endian.is_null() && raw_type_size(a.type) > 1)
        throw refuse("needs 'endian' for a type wider than a byte");
      if (!endian.is_null() && endian != "little" && endian != "big")
        throw refuse("has an 'endian' other than \"little\" or \"big\"");
      c.big_endian = endian == "big" && raw_type_size(a.type) > 1;
    } else if (codec.name == "crc32c") {
      if (stage == arrays) throw refuse("comes before the array's bytes codec");
      (c.codecs.compressor == ZarrCompressor::none ? c.codecs.checksums_inside
                                                   : c.codecs.checksums_outside)++;
    } else if (codec.name == "gzip" || codec.name == "zstd" || codec.name == "blosc") {
      if (stage == arrays) throw refuse("comes before the array's bytes codec");
      if (c.codecs.compressor != ZarrCompressor::none)
        throw refuse(fmt::format("follows '{}': one compressor per chunk is read",
                                 zarr_compressor_name(c.codecs.compressor)));
      if (codec.name == "blosc") {
        const json shuffle = config.value("shuffle", json("noshuffle"));
        if (shuffle != "noshuffle" && shuffle != "shuffle" && shuffle != "bitshuffle")
          throw refuse("has a 'shuffle' other than noshuffle, shuffle or bitshuffle");
      }
      c.codecs.compressor = codec.name == "gzip"   ? ZarrCompressor::gzip
                            : codec.name == "zstd" ? ZarrCompressor::zstd
                                                   : ZarrCompressor::blosc;
      stage = after;
    } else if (codec.name == "sharding_indexed") {
      throw refuse("inside a shard is not read (one level of sharding)");
    } else {
      // A codec changes the bytes: one not known cannot be skipped, whatever must_understand says.
      throw refuse(
          "is not supported (read: bytes, transpose, gzip, zstd, blosc, crc32c, "
          "sharding_indexed)");
    }
  }
  if (stage == arrays)
    throw zarr_bad_field(a.what, field, list, "has no array-to-bytes codec ('bytes')");
  if (c.sharding && (c.codecs.compressor != ZarrCompressor::none ||
                     c.codecs.checksums_inside + c.codecs.checksums_outside > 0))
    throw zarr_bad_field(a.what, field, list,
                         "has codecs after sharding_indexed: whole-shard encodings are not read");
  return c;
}

void parse_sharding(const json& config, const std::vector<int64_t>& outer, ZarrArray& a) {
  const std::string field = "codecs.sharding_indexed";
  ZarrShard s;
  s.shape = outer;
  if (!config.contains("chunk_shape"))
    throw Error(fmt::format("{}: missing field '{}.chunk_shape'", a.what, field));
  a.chunks = zarr_sizes(config["chunk_shape"], field + ".chunk_shape", a.what, 1);
  if (a.chunks.size() != outer.size())
    throw zarr_bad_field(
        a.what, field + ".chunk_shape", config["chunk_shape"],
        fmt::format("has {} sizes, the shard has {}", a.chunks.size(), outer.size()));
  s.inner_chunks = 1;
  for (size_t d = 0; d < outer.size(); ++d) {
    if (outer[d] % a.chunks[d] != 0)
      throw zarr_bad_field(
          a.what, field + ".chunk_shape", config["chunk_shape"],
          fmt::format("does not divide the shard's shape ({} in dimension {})", outer[d], d));
    s.per_shard.push_back(outer[d] / a.chunks[d]);
    s.inner_chunks *= static_cast<uint64_t>(s.per_shard.back());
    if (s.inner_chunks > kMaxInnerChunks)
      throw zarr_bad_field(
          a.what, field + ".chunk_shape", config["chunk_shape"],
          fmt::format("gives shards of more than {} inner chunks", kMaxInnerChunks));
  }
  if (!config.contains("codecs"))
    throw Error(fmt::format("{}: missing field '{}.codecs'", a.what, field));
  const Chain inner = parse_chain(config["codecs"], field + ".codecs", a, false);
  a.codecs = inner.codecs;
  a.big_endian = inner.big_endian;
  // The index has a fixed size: its "bytes" and checksums only.
  const json index = config.value("index_codecs", json());
  const Chain ic = parse_chain(index, field + ".index_codecs", a, false);
  if (ic.codecs.compressor != ZarrCompressor::none || !ic.codecs.order.empty())
    throw zarr_bad_field(a.what, field + ".index_codecs", index,
                         "may only hold 'bytes' and 'crc32c' (an index of a fixed size)");
  s.index_big_endian = false;
  for (const json& e : index)
    if (named(e, field, a.what).name == "bytes" && e.is_object() && e.contains("configuration"))
      s.index_big_endian = e["configuration"].value("endian", "little") == "big";
  s.index_checksums = ic.codecs.checksums_inside + ic.codecs.checksums_outside;
  const json location = config.value("index_location", json("end"));
  if (location != "start" && location != "end")
    throw zarr_bad_field(a.what, field + ".index_location", location,
                         "is not \"start\" or \"end\"");
  s.index_at_start = location == "start";
  a.shard = std::move(s);
}

// Fields beyond the core's: an object with "must_understand": false may be ignored; anything
// else is an extension this reader would misread.
void refuse_extensions(const json& doc, const std::string& what) {
  static const char* known[] = {
      "zarr_format",         "node_type",  "shape",  "data_type",  "chunk_grid",
      "chunk_key_encoding",  "fill_value", "codecs", "attributes", "dimension_names",
      "storage_transformers"};
  for (const auto& [key, value] : doc.items()) {
    if (std::find(std::begin(known), std::end(known), key) != std::end(known)) continue;
    if (value.is_object() && value.contains("must_understand") && value["must_understand"] == false)
      continue;
    throw zarr_bad_field(what, key, value,
                         "is an extension this reader does not know, and it must be understood");
  }
}

}  // namespace

ZarrArray parse_zarr_json_array(std::string_view text, const std::filesystem::path& dir,
                                const std::string& what) {
  ZarrArray a;
  a.dir = dir;
  a.what = what;
  a.zarr_format = 3;
  const json doc = parse_zarr_json(text, what);
  if (!doc.contains("zarr_format") || doc["zarr_format"] != 3)
    throw zarr_bad_field(what, "zarr_format",
                         doc.contains("zarr_format") ? doc["zarr_format"] : json(),
                         "is not 3 (zarr.json is Zarr v3 metadata)");
  if (doc.value("node_type", json()) != "array")
    throw zarr_bad_field(what, "node_type", doc.value("node_type", json()),
                         "is not \"array\" (a group holds no voxels)");
  refuse_extensions(doc, what);
  if (!doc.contains("shape")) throw Error(fmt::format("{}: missing field 'shape'", what));
  a.shape = zarr_sizes(doc["shape"], "shape", what, 1);
  uint64_t total = 1;
  for (int64_t n : a.shape)
    if (__builtin_mul_overflow(total, static_cast<uint64_t>(n), &total))
      throw zarr_bad_field(what, "shape", doc["shape"], "has more elements than 2^64");
  parse_data_type(doc, a);
  if (!doc.contains("chunk_grid")) throw Error(fmt::format("{}: missing field 'chunk_grid'", what));
  const Named grid = named(doc["chunk_grid"], "chunk_grid", what);
  if (grid.name != "regular" || !grid.configuration.contains("chunk_shape"))
    throw zarr_bad_field(what, "chunk_grid", doc["chunk_grid"],
                         "is not supported (only \"regular\" with a 'chunk_shape')");
  const std::vector<int64_t> outer =
      zarr_sizes(grid.configuration["chunk_shape"], "chunk_grid.chunk_shape", what, 1);
  if (outer.size() != a.shape.size())
    throw zarr_bad_field(what, "chunk_grid", doc["chunk_grid"],
                         fmt::format("has {} sizes, 'shape' has {}", outer.size(), a.shape.size()));
  a.chunks = outer;
  parse_key_encoding(doc, a);
  if (doc.contains("storage_transformers") &&
      !(doc["storage_transformers"].is_array() && doc["storage_transformers"].empty()))
    throw zarr_bad_field(what, "storage_transformers", doc["storage_transformers"],
                         "is not supported (only an empty list)");
  if (!doc.contains("codecs")) throw Error(fmt::format("{}: missing field 'codecs'", what));
  const Chain chain = parse_chain(doc["codecs"], "codecs", a, true);
  if (chain.sharding) {
    if (!chain.codecs.order.empty() &&
        !std::is_sorted(chain.codecs.order.begin(), chain.codecs.order.end()))
      throw zarr_bad_field(what, "codecs", doc["codecs"],
                           "transposes the shards: only a transpose inside the shard is read");
    parse_sharding(*chain.sharding, outer, a);
  } else {
    a.codecs = chain.codecs;
    a.big_endian = chain.big_endian;
  }
  if (!doc.contains("fill_value")) throw Error(fmt::format("{}: missing field 'fill_value'", what));
  set_zarr_fill(doc["fill_value"], a, true);
  if (doc.contains("dimension_names")) {
    const json& names = doc["dimension_names"];
    if (!names.is_array() || names.size() != a.shape.size())
      throw zarr_bad_field(what, "dimension_names", names,
                           fmt::format("must list {} names", a.shape.size()));
    for (const json& n : names) {
      if (!n.is_null() && !n.is_string())
        throw zarr_bad_field(what, "dimension_names", names, "must hold strings or null");
      a.dimension_names.push_back(n.is_string() ? n.get<std::string>() : "");
    }
  }
  set_zarr_chunk_bytes(a, a.shard ? "codecs.sharding_indexed.chunk_shape" : "chunk_grid",
                       a.shard ? doc["codecs"] : doc["chunk_grid"]);
  return a;
}

}  // namespace imx::detail
