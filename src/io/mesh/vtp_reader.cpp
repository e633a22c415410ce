// XML PolyData (.vtp), read with expat; the appended data after the XML is read by offset.
#include <expat.h>

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <cstring>
#include <map>
#include <memory>
#include <optional>
#include <string_view>
#include <type_traits>

#include <fmt/format.h>
#include <glm/glm.hpp>

#include "intermix/error.hpp"
#include "io/mesh/mesh_space.hpp"
#include "io/mesh/polydata.hpp"
#include "io/streams/base64.hpp"
#include "io/streams/bounded_inflate.hpp"
#include "io/streams/byte_cursor.hpp"
#include "io/streams/header_text.hpp"
#include "io/streams/inflate_charge.hpp"
#include "io/streams/xml_parser.hpp"

namespace imx::detail {
namespace {

constexpr uint64_t kMaxValues = uint64_t{1} << 31;

struct TypeInfo {
  int bytes;
  int kind;  // 0 unsigned, 1 signed, 2 float
};

std::optional<TypeInfo> type_info(std::string_view name) {
  static const std::map<std::string_view, TypeInfo> table = {
      {"Int8", {1, 1}},    {"UInt8", {1, 0}},   {"Int16", {2, 1}},  {"UInt16", {2, 0}},
      {"Int32", {4, 1}},   {"UInt32", {4, 0}},  {"Int64", {8, 1}},  {"UInt64", {8, 0}},
      {"Float32", {4, 2}}, {"Float64", {8, 2}}, {"String", {1, 0}}, {"Char", {1, 1}},
  };
  auto it = table.find(name);
  if (it == table.end()) return std::nullopt;
  return it->second;
}

// One <DataArray> as the XML gives it; its values are decoded once the whole XML is read.
struct ArrayRef {
  std::string section;  // Points, Polys, Strips, PointData, FieldData, ...
  int piece = -1;
  std::string name, type, format;
  int components = 1;
  uint64_t offset = 0;  // appended
  std::string text;     // ascii or binary (base64) content
};

struct PieceInfo {
  uint64_t points = 0, polys = 0, strips = 0;
  uint64_t verts = 0, lines = 0;
  std::string normals;  // PointData's Normals attribute: the array that is the normals
};

// Bytes from raw data or from base64 text, read on demand. Base64 is decoded group by group of
// four characters, a padded group giving fewer bytes and decoding going on after it: VTK
// encodes a binary header and its data either as one stream or as two, and both read alike.
class ByteSource {
 public:
  ByteSource(std::string_view data, bool base64) : data_(data), base64_(base64) {}

  // Appends `n` more bytes to `out`; false when the data ends first.
  bool read(size_t n, std::string& out) {
    if (!base64_) {
      if (n > data_.size() - pos_) return false;
      out.append(data_.substr(pos_, n));
      pos_ += n;
      return true;
    }
    while (pending_.size() < n) {
      if (!decode_plain_groups(n - pending_.size()) && !decode_group()) return false;
    }
    out.append(pending_, 0, n);
    pending_.erase(0, n);
    return true;
  }

  // How many more bytes there can at most be (for bounds before allocating).
  size_t bound() const {
    return base64_ ? pending_.size() + (data_.size() - pos_) / 4 * 3 + 3 : data_.size() - pos_;
  }

 private:
  // The fast path for long arrays: runs of four base64 characters (no white space, no padding)
  // decoded at once, enough for `want` bytes. False when the next group is not such a run.
  bool decode_plain_groups(size_t want) {
    static constexpr auto kValue = [] {
      std::array<int8_t, 256> t{};
      for (int c = 0; c < 256; ++c) t[c] = static_cast<int8_t>(base64_value(c));
      return t;
    }();
    const size_t groups = std::min((want + 2) / 3, (data_.size() - pos_) / 4);
    const size_t before = pending_.size();
    pending_.resize(before + 3 * groups);
    size_t done = 0;
    for (; done < groups; ++done) {
      const auto* c = reinterpret_cast<const unsigned char*>(data_.data() + pos_);
      const int a = kValue[c[0]], b = kValue[c[1]], d = kValue[c[2]], e = kValue[c[3]];
      if ((a | b | d | e) < 0) break;
      const uint32_t quad = static_cast<uint32_t>(a << 18 | b << 12 | d << 6 | e);
      char* out = pending_.data() + before + 3 * done;
      out[0] = static_cast<char>(quad >> 16);
      out[1] = static_cast<char>(quad >> 8);
      out[2] = static_cast<char>(quad);
      pos_ += 4;
    }
    pending_.resize(before + 3 * done);
    return done > 0;
  }

  bool decode_group() {
    int chars = 0, pad = 0;
    uint32_t quad = 0;
    while (chars + pad < 4) {
      if (pos_ >= data_.size()) return false;
      const auto c = static_cast<unsigned char>(data_[pos_++]);
      if (std::isspace(c)) continue;
      if (c == '=') {
        ++pad;
        continue;
      }
      const int v = base64_value(c);
      if (v < 0 || pad > 0) throw Error("the base64 data holds a character that is not base64");
      quad = (quad << 6) | static_cast<uint32_t>(v);
      ++chars;
    }
    if (chars < 2) throw Error("the base64 data has a group of fewer than 2 characters");
    quad <<= 6 * pad;
    const char bytes[3] = {static_cast<char>(quad >> 16), static_cast<char>(quad >> 8),
                           static_cast<char>(quad)};
    pending_.append(bytes, static_cast<size_t>(chars - 1));
    return true;
  }

  std::string_view data_;
  bool base64_;
  size_t pos_ = 0;
  std::string pending_;
};

struct Parser {
  std::string what;
  XML_Parser xml = nullptr;
  std::string fault;
  std::vector<std::string> stack;
  std::string type, byte_order = "LittleEndian", header_type = "UInt32", compressor;
  bool seen_root = false;
  std::vector<PieceInfo> pieces;
  std::vector<ArrayRef> arrays;
  bool in_array = false;
  uint64_t text_limit = 0;  // the file's size: no array text is longer
  bool keep_lines = false;

  void fail(std::string message) {
    if (fault.empty()) fault = std::move(message);
    XML_StopParser(xml, XML_FALSE);
  }

  static std::map<std::string, std::string, std::less<>> attributes(const char** attrs) {
    std::map<std::string, std::string, std::less<>> a;
    for (const char** p = attrs; p[0] && p[1]; p += 2) a[p[0]] = p[1];
    return a;
  }

  std::optional<uint64_t> count(const std::map<std::string, std::string, std::less<>>& a,
                                const char* key) {
    auto it = a.find(key);
    if (it == a.end()) return uint64_t{0};
    std::optional<int64_t> v = parse_header_number<int64_t>(it->second);
    if (!v || *v < 0 || static_cast<uint64_t>(*v) > kMaxValues) {
      fail(fmt::format("{} '{}' is not a count", key, shown(it->second)));
      return std::nullopt;
    }
    return static_cast<uint64_t>(*v);
  }

  void start(const char* name, const char** attrs) {
    if (!fault.empty()) return;
    const std::string_view n = name;
    const auto a = attributes(attrs);
    if (stack.empty()) {
      if (n != "VTKFile")
        return fail(fmt::format("the root element is <{}>, not <VTKFile>", shown(n)));
      auto get = [&](const char* k, std::string fallback) {
        auto it = a.find(k);
        return it == a.end() ? fallback : it->second;
      };
      type = get("type", "");
      byte_order = get("byte_order", "LittleEndian");
      header_type = get("header_type", "UInt32");
      compressor = get("compressor", "");
      if (type != "PolyData")
        return fail(
            fmt::format("a VTK XML '{}' file: intermix reads PolyData (.vtp)", shown(type)));
      if (byte_order != "LittleEndian" && byte_order != "BigEndian")
        return fail(
            fmt::format("byte_order '{}' is not LittleEndian or BigEndian", shown(byte_order)));
      if (header_type != "UInt32" && header_type != "UInt64")
        return fail(fmt::format("header_type '{}' is not UInt32 or UInt64", shown(header_type)));
      if (!compressor.empty() && compressor != "vtkZLibDataCompressor")
        return fail(
            fmt::format("compressor '{}' is not read (intermix reads uncompressed and "
                        "vtkZLibDataCompressor data)",
                        shown(compressor)));
      seen_root = true;
    } else if (n == "Piece" && stack.back() == "PolyData") {
      PieceInfo p;
      auto points = count(a, "NumberOfPoints"), polys = count(a, "NumberOfPolys"),
           strips = count(a, "NumberOfStrips");
      if (!points || !polys || !strips) return;
      p.points = *points;
      p.polys = *polys;
      p.strips = *strips;
      if (keep_lines) {
        auto verts = count(a, "NumberOfVerts"), lines = count(a, "NumberOfLines");
        if (!verts || !lines) return;
        p.verts = *verts;
        p.lines = *lines;
      }
      if (pieces.size() >= 4096) return fail("more than 4096 pieces");
      pieces.push_back(p);
    } else if (n == "PointData" && !pieces.empty()) {
      auto it = a.find("Normals");
      if (it != a.end()) pieces.back().normals = it->second;
    } else if (n == "DataArray" || n == "Array") {
      if (in_array) return fail("a <DataArray> inside another");
      ArrayRef r;
      r.section = stack.back();
      r.piece = static_cast<int>(pieces.size()) - 1;
      auto get = [&](const char* k) {
        auto it = a.find(k);
        return it == a.end() ? std::string() : it->second;
      };
      r.name = get("Name");
      r.type = get("type");
      r.format = get("format");
      if (!type_info(r.type))
        return fail(fmt::format("data array '{}': type '{}' is not a type intermix reads",
                                shown(r.name), shown(r.type)));
      if (r.format != "ascii" && r.format != "binary" && r.format != "appended")
        return fail(fmt::format("data array '{}': format '{}' is not ascii, binary or appended",
                                shown(r.name), shown(r.format)));
      const std::string comps = get("NumberOfComponents");
      if (!comps.empty()) {
        std::optional<int64_t> c = parse_header_number<int64_t>(comps);
        if (!c || *c < 1 || *c > 64)
          return fail(fmt::format("data array '{}': NumberOfComponents '{}' is not 1 to 64",
                                  shown(r.name), shown(comps)));
        r.components = static_cast<int>(*c);
      }
      if (r.format == "appended") {
        std::optional<int64_t> o = parse_header_number<int64_t>(get("offset"));
        if (!o || *o < 0)
          return fail(fmt::format("data array '{}': offset '{}' is not an offset", shown(r.name),
                                  shown(get("offset"))));
        r.offset = static_cast<uint64_t>(*o);
      }
      if (arrays.size() >= 65536) return fail("more than 65536 data arrays");
      arrays.push_back(std::move(r));
      in_array = true;
    }
    stack.emplace_back(n);
  }

  void end() {
    if (!fault.empty()) return;
    if (!stack.empty() && (stack.back() == "DataArray" || stack.back() == "Array"))
      in_array = false;
    if (!stack.empty()) stack.pop_back();
  }

  void text(std::string_view s) {
    // Only the array's own text: VTK 9 nests <InformationKey> elements (ranges) in an array.
    if (!fault.empty() || !in_array || (stack.back() != "DataArray" && stack.back() != "Array"))
      return;
    std::string& t = arrays.back().text;
    if (t.size() + s.size() > text_limit)
      return fail("a data array's text is longer than the file");
    t += s;
  }
};

// The value bytes of one array, decompressed: from base64 text (format binary) or the appended
// data (raw or base64). Each array's bytes are charged to the file's InflateCharge before they
// are allocated: arrays whose offsets all name one compressed block cost once each.
class Decoder {
 public:
  Decoder(const Parser& p, std::string_view appended, bool appended_base64, std::string what)
      : big_(p.byte_order == "BigEndian"),
        header_bytes_(p.header_type == "UInt64" ? 8 : 4),
        compressed_(!p.compressor.empty()),
        appended_(appended),
        appended_base64_(appended_base64),
        what_(std::move(what)) {}

  std::string bytes(const ArrayRef& r, InflateCharge& charge) const {
    const std::string field = fmt::format("data array '{}' ({})", shown(r.name), r.section);
    std::optional<ByteSource> source;
    if (r.format == "binary") {
      source.emplace(r.text, true);
    } else {
      if (appended_.data() == nullptr)
        fail(fmt::format("{} is appended, but the file has no <AppendedData>", field));
      if (r.offset > appended_.size())
        fail(fmt::format("{}: offset {} is past the appended data's {} bytes", field, r.offset,
                         appended_.size()));
      source.emplace(appended_.substr(static_cast<size_t>(r.offset)), appended_base64_);
    }
    try {
      return compressed_ ? inflate_blocks(*source, field, charge) : plain(*source, field, charge);
    } catch (const Error& e) {
      const std::string m = e.what();
      if (m.starts_with(what_)) throw;
      fail(fmt::format("{}: {}", field, m));
    }
  }

  [[noreturn]] void fail(const std::string& why) const {
    throw Error(fmt::format("{}: {}", what_, why));
  }

  bool big_endian() const { return big_; }

 private:
  uint64_t header(ByteSource& s, const std::string& field) const {
    std::string raw;
    if (!s.read(static_cast<size_t>(header_bytes_), raw))
      fail(fmt::format("{}: the data ends inside its header", field));
    ByteCursor c(raw, what_, big_);
    return header_bytes_ == 8 ? c.read<uint64_t>("a header") : c.read<uint32_t>("a header");
  }

  std::string plain(ByteSource& s, const std::string& field, InflateCharge& charge) const {
    const uint64_t n = header(s, field);
    if (n > s.bound())
      fail(fmt::format("{}: its header claims {} bytes, more than the data holds", field, n));
    charge.charge(n, field);
    std::string out;
    if (!s.read(static_cast<size_t>(n), out))
      fail(fmt::format("{}: its header claims {} bytes, more than the data holds", field, n));
    return out;
  }

  std::string inflate_blocks(ByteSource& s, const std::string& field, InflateCharge& charge) const {
    const uint64_t blocks = header(s, field);
    const uint64_t block_size = header(s, field);
    const uint64_t last_size = header(s, field);
    if (blocks > s.bound() / 2)
      fail(fmt::format("{}: {} compressed blocks are more than the data holds", field, blocks));
    std::vector<uint64_t> sizes(static_cast<size_t>(blocks));
    uint64_t compressed_total = 0;
    for (uint64_t& z : sizes) {
      z = header(s, field);
      compressed_total += z;
    }
    if (compressed_total > s.bound())
      fail(fmt::format("{}: the blocks claim {} compressed bytes, more than the data holds", field,
                       compressed_total));
    const uint64_t total =
        blocks == 0 ? 0 : (blocks - 1) * block_size + (last_size == 0 ? block_size : last_size);
    if (blocks > 0 && (block_size == 0 || total / blocks > block_size + 1 ||
                       total > compressed_total * 1032 + 1024))
      fail(fmt::format("{}: {} blocks of {} bytes cannot come from {} compressed bytes", field,
                       blocks, block_size, compressed_total));
    charge.charge(total, fmt::format("{}, inflated,", field));
    std::string out(static_cast<size_t>(total), '\0');
    auto* at = reinterpret_cast<uint8_t*>(out.data());
    std::string packed;
    for (uint64_t b = 0; b < blocks; ++b) {
      packed.clear();
      if (!s.read(static_cast<size_t>(sizes[b]), packed))
        fail(fmt::format("{}: the data ends inside compressed block {}", field, b));
      const auto want =
          static_cast<size_t>(b + 1 == blocks && last_size != 0 ? last_size : block_size);
      inflate_exactly(std::span(reinterpret_cast<const uint8_t*>(packed.data()), packed.size()),
                      std::span(at, want), fmt::format("compressed block {}", b).c_str(),
                      fmt::format("{}: {}", what_, field));
      at += want;
    }
    return out;
  }

  bool big_;
  int header_bytes_;
  bool compressed_;
  std::string_view appended_;
  bool appended_base64_;
  std::string what_;
};

// The whitespace-separated words of an ascii array (across lines).
std::vector<std::string_view> words(std::string_view s) {
  std::vector<std::string_view> out;
  size_t i = 0;
  while (i < s.size()) {
    while (i < s.size() && std::isspace(static_cast<unsigned char>(s[i]))) ++i;
    size_t e = i;
    while (e < s.size() && !std::isspace(static_cast<unsigned char>(s[e]))) ++e;
    if (e > i) out.push_back(s.substr(i, e - i));
    i = e;
  }
  return out;
}

// An array's values as doubles (a String array's bytes, 0-terminated strings). The doubles stay
// charged to `charge` (the caller releases them once it has let them go); the decoded bytes are
// released here.
std::vector<double> decode(const ArrayRef& r, const Decoder& d, const std::string& what,
                           InflateCharge& charge) {
  const TypeInfo t = *type_info(r.type);
  std::vector<double> out;
  if (r.format == "ascii") {
    for (const std::string_view w : words(r.text)) {
      std::optional<double> v = parse_header_number<double>(w);
      if (!v)
        throw Error(fmt::format("{}: data array '{}': '{}' is not a number", what, shown(r.name),
                                shown(w)));
      out.push_back(*v);
    }
    charge.charge(out.size() * sizeof(double),
                  fmt::format("data array '{}' ({}) as numbers", shown(r.name), r.section));
    return out;
  }
  const std::string bytes = d.bytes(r, charge);
  if (bytes.size() % static_cast<size_t>(t.bytes) != 0)
    throw Error(fmt::format("{}: data array '{}' has {} bytes, not a whole number of {} values",
                            what, shown(r.name), bytes.size(), r.type));
  charge.charge(bytes.size() / static_cast<size_t>(t.bytes) * sizeof(double),
                fmt::format("data array '{}' ({}) as numbers", shown(r.name), r.section));
  ByteCursor c(bytes, what, d.big_endian());
  out.reserve(bytes.size() / static_cast<size_t>(t.bytes));
  while (!c.at_end()) {
    double v = 0.0;
    if (t.kind == 2)
      v = t.bytes == 4 ? c.read<float>("a value") : c.read<double>("a value");
    else if (t.bytes == 1)
      v = t.kind == 1 ? c.read<int8_t>("a value") : c.read<uint8_t>("a value");
    else if (t.bytes == 2)
      v = t.kind == 1 ? c.read<int16_t>("a value") : c.read<uint16_t>("a value");
    else if (t.bytes == 4)
      v = t.kind == 1 ? c.read<int32_t>("a value") : c.read<uint32_t>("a value");
    else
      v = t.kind == 1 ? static_cast<double>(c.read<int64_t>("a value"))
                      : static_cast<double>(c.read<uint64_t>("a value"));
    out.push_back(v);
  }
  charge.release(bytes.size());
  return out;
}

// The first string of a String array's values.
std::string first_string(const std::vector<double>& chars) {
  std::string s;
  for (double c : chars) {
    if (c == 0.0) break;
    s += static_cast<char>(static_cast<int>(c) & 0xFF);
  }
  return s;
}

void add_cells(PolyDataFile& out, const std::vector<double>& connectivity,
               const std::vector<double>& offsets, uint64_t cells, uint64_t base, uint64_t points,
               bool strips, const std::string& what) {
  if (offsets.size() != cells)
    throw Error(fmt::format("{}: {} offsets for {} cells", what, offsets.size(), cells));
  std::vector<int64_t> cell;
  double start = 0.0;
  for (size_t c = 0; c < offsets.size(); ++c) {
    const double end = offsets[c];
    if (!(end >= start && end <= static_cast<double>(connectivity.size())))
      throw Error(fmt::format("{}: cell {} ends at offset {}, outside {}..{}", what, c, end, start,
                              connectivity.size()));
    cell.clear();
    for (auto k = static_cast<size_t>(start); k < static_cast<size_t>(end); ++k)
      cell.push_back(static_cast<int64_t>(connectivity[k]) + static_cast<int64_t>(base));
    const std::string cell_what = fmt::format("{} cell {}", what, c);
    if (strips)
      add_strip(out.mesh, cell, base + points, cell_what);
    else
      add_polygon(out.mesh, cell, base + points, cell_what);
    start = end;
  }
}

// One piece's Lines cells, appended to `lines` with their point indices (each checked against
// the piece's `points`) shifted by `base`.
void add_lines(PolyLines& lines, const std::vector<double>& connectivity,
               const std::vector<double>& offsets, uint64_t cells, uint64_t base, uint64_t points,
               const std::string& what) {
  if (offsets.size() != cells)
    throw Error(fmt::format("{}: {} offsets for {} cells", what, offsets.size(), cells));
  double start = 0.0;
  for (size_t c = 0; c < offsets.size(); ++c) {
    const double end = offsets[c];
    if (!(end >= start && end <= static_cast<double>(connectivity.size())))
      throw Error(fmt::format("{}: cell {} ends at offset {}, outside {}..{}", what, c, end, start,
                              connectivity.size()));
    for (auto k = static_cast<size_t>(start); k < static_cast<size_t>(end); ++k) {
      const double v = connectivity[k];
      if (!(v >= 0.0 && v < static_cast<double>(points)))
        throw Error(fmt::format("{} cell {}: point index {} is not one of the piece's {} points",
                                what, c, v, points));
      lines.indices.push_back(static_cast<int64_t>(v) + static_cast<int64_t>(base));
    }
    lines.offsets.push_back(lines.indices.size());
    start = end;
  }
}

}  // namespace

PolyDataFile read_vtp(const std::filesystem::path& file, bool keep_lines) {
  const std::string what = file.string();
  const std::string bytes = read_file_bytes(file);
  // The appended data is not XML: expat reads what comes before it.
  const size_t appended_at = bytes.find("<AppendedData");
  std::string_view appended;
  bool appended_base64 = false;
  if (appended_at != std::string::npos) {
    const size_t close = bytes.find('>', appended_at);
    if (close == std::string::npos) throw Error(fmt::format("{}: <AppendedData has no '>'", what));
    const std::string_view tag = std::string_view(bytes).substr(appended_at, close - appended_at);
    if (tag.find("encoding=\"base64\"") != std::string_view::npos)
      appended_base64 = true;
    else if (tag.find("encoding=\"raw\"") == std::string_view::npos)
      throw Error(fmt::format("{}: <AppendedData> encoding is not raw or base64", what));
    const size_t underscore = bytes.find('_', close);
    const std::string_view before = std::string_view(bytes).substr(
        close + 1, underscore == std::string::npos ? 0 : underscore - close - 1);
    if (underscore == std::string::npos || !std::all_of(before.begin(), before.end(), [](char c) {
          return std::isspace(static_cast<unsigned char>(c)) != 0;
        }))
      throw Error(fmt::format("{}: <AppendedData> does not start with '_'", what));
    appended = std::string_view(bytes).substr(underscore + 1);
  }
  Parser p;
  p.what = what;
  p.text_limit = bytes.size();
  p.keep_lines = keep_lines;
  const XmlParser xml = make_xml_parser();
  if (!xml) throw Error(fmt::format("{}: cannot start the XML parser", what));
  p.xml = xml.get();
  XML_SetUserData(p.xml, &p);
  XML_SetElementHandler(
      p.xml,
      [](void* u, const char* name, const char** attrs) {
        auto* self = static_cast<Parser*>(u);
        try {
          self->start(name, attrs);
        } catch (const std::exception& e) {
          self->fail(e.what());
        }
      },
      [](void* u, const char*) { static_cast<Parser*>(u)->end(); });
  XML_SetCharacterDataHandler(p.xml, [](void* u, const char* s, int len) {
    static_cast<Parser*>(u)->text({s, static_cast<size_t>(len)});
  });
  XML_SetEntityDeclHandler(
      p.xml, [](void* u, const char*, int, const char*, int, const char*, const char*, const char*,
                const char*) { static_cast<Parser*>(u)->fail("the file declares XML entities"); });
  const size_t xml_size = appended_at == std::string::npos ? bytes.size() : appended_at;
  const bool whole = appended_at == std::string::npos;
  if (xml_size > static_cast<size_t>(INT32_MAX))
    throw Error(fmt::format("{}: the XML part is over 2 GiB", what));
  if (XML_Parse(p.xml, bytes.data(), static_cast<int>(xml_size), whole ? XML_TRUE : XML_FALSE) ==
      XML_STATUS_ERROR) {
    if (!p.fault.empty()) throw Error(fmt::format("{}: {}", what, p.fault));
    throw Error(fmt::format("{}: not a VTK XML file: {} at line {}", what,
                            XML_ErrorString(XML_GetErrorCode(p.xml)),
                            XML_GetCurrentLineNumber(p.xml)));
  }
  if (!p.fault.empty()) throw Error(fmt::format("{}: {}", what, p.fault));
  if (!p.seen_root) throw Error(fmt::format("{}: not a VTK XML file (no <VTKFile>)", what));
  if (p.pieces.empty()) throw Error(fmt::format("{}: the PolyData has no <Piece>", what));

  const Decoder decoder(p, appended, appended_base64, what);
  PolyDataFile out;
  uint64_t total_points = 0;
  for (const PieceInfo& piece : p.pieces) total_points += piece.points;
  // Everything decoded from the file is charged here, against one budget.
  InflateCharge charge(what);
  // The mesh's positions, normals and colours.
  charge.charge(total_points * 40, fmt::format("NumberOfPoints {}", total_points));
  // Values decoded only to be copied elsewhere: their charge goes with them.
  auto let_go = [&](const std::vector<double>& v) { charge.release(v.size() * sizeof(double)); };
  std::map<std::string, size_t> data_index;  // point data arrays by name
  uint64_t base = 0;
  for (size_t k = 0; k < p.pieces.size(); ++k) {
    const PieceInfo& piece = p.pieces[k];
    const std::string piece_what = fmt::format("{}: piece {}", what, k);
    auto find = [&](std::string_view section, std::string_view name) -> const ArrayRef* {
      for (const ArrayRef& r : p.arrays)
        if (r.piece == static_cast<int>(k) && r.section == section &&
            (name.empty() || r.name == name))
          return &r;
      return nullptr;
    };
    const ArrayRef* points = find("Points", "");
    if (!points && piece.points > 0)
      throw Error(fmt::format("{} has {} points but no <Points> array", piece_what, piece.points));
    if (points) {
      if (points->components != 3)
        throw Error(
            fmt::format("{}: <Points> has {} components, not 3", piece_what, points->components));
      const std::vector<double> xyz = decode(*points, decoder, what, charge);
      if (xyz.size() != piece.points * 3)
        throw Error(fmt::format("{}: <Points> holds {} values, NumberOfPoints {} needs {}",
                                piece_what, xyz.size(), piece.points, piece.points * 3));
      for (size_t i = 0; i + 2 < xyz.size(); i += 3)
        out.mesh.positions.emplace_back(xyz[i], xyz[i + 1], xyz[i + 2]);
      let_go(xyz);
    }
    for (const char* section : {"Polys", "Strips"}) {
      const uint64_t cells = std::string_view(section) == "Polys" ? piece.polys : piece.strips;
      const ArrayRef* connectivity = find(section, "connectivity");
      const ArrayRef* offsets = find(section, "offsets");
      if (cells == 0 || keep_lines) continue;
      if (!connectivity || !offsets)
        throw Error(
            fmt::format("{}: <{}> lacks its connectivity or offsets array", piece_what, section));
      const std::vector<double> c = decode(*connectivity, decoder, what, charge);
      const std::vector<double> o = decode(*offsets, decoder, what, charge);
      const size_t before = out.mesh.triangles.size();
      add_cells(out, c, o, cells, base, piece.points, std::string_view(section) == "Strips",
                fmt::format("{} {}", piece_what, section));
      let_go(c);
      let_go(o);
      charge.charge((out.mesh.triangles.size() - before) * sizeof(glm::uvec3),
                    fmt::format("{}'s triangles", section));
    }
    if (keep_lines && piece.lines > 0) {
      const ArrayRef* connectivity = find("Lines", "connectivity");
      const ArrayRef* offsets = find("Lines", "offsets");
      if (!connectivity || !offsets)
        throw Error(fmt::format("{}: <Lines> lacks its connectivity or offsets array", piece_what));
      const std::vector<double> c = decode(*connectivity, decoder, what, charge);
      const std::vector<double> o = decode(*offsets, decoder, what, charge);
      add_lines(out.lines, c, o, piece.lines, base, piece.points, piece_what + " Lines");
      let_go(c);
      let_go(o);
    }
    // Cell data, ordered vertices, lines, polygons, strips: the lines' tuples of each array.
    for (size_t i = 0; keep_lines && i < p.arrays.size(); ++i) {
      const ArrayRef& r = p.arrays[i];
      if (r.piece != static_cast<int>(k) || r.section != "CellData") continue;
      const std::vector<double> v = decode(r, decoder, what, charge);  // its lines' part is kept
      const uint64_t cells = piece.verts + piece.lines + piece.polys + piece.strips;
      const auto c = static_cast<uint64_t>(r.components);
      if (v.size() != cells * c)
        throw Error(fmt::format("{}: cell data '{}' holds {} values, {} cells of {} need {}",
                                piece_what, shown(r.name), v.size(), cells, c, cells * c));
      auto d = std::find_if(out.line_data.begin(), out.line_data.end(),
                            [&](const MeshPointData& m) { return m.name == r.name; });
      if (d == out.line_data.end()) {
        if (k > 0)
          throw Error(
              fmt::format("{}: cell data '{}' is not in every piece", piece_what, shown(r.name)));
        d = out.line_data.insert(out.line_data.end(), {r.name, r.components, {}});
      }
      if (d->components != r.components)
        throw Error(
            fmt::format("{}: cell data '{}' changes its components", piece_what, shown(r.name)));
      d->values.insert(d->values.end(), v.begin() + static_cast<ptrdiff_t>(piece.verts * c),
                       v.begin() + static_cast<ptrdiff_t>((piece.verts + piece.lines) * c));
    }
    // Point data: the normals, and every other array as the file names it.
    std::vector<glm::vec3> normals;
    for (const ArrayRef& r : p.arrays) {
      if (r.piece != static_cast<int>(k) || r.section != "PointData") continue;
      std::vector<double> v = decode(r, decoder, what, charge);  // kept, but for the normals
      if (v.size() != piece.points * static_cast<uint64_t>(r.components))
        throw Error(fmt::format("{}: point data '{}' holds {} values, {} points of {} need {}",
                                piece_what, shown(r.name), v.size(), piece.points, r.components,
                                piece.points * r.components));
      if (!piece.normals.empty() && r.name == piece.normals && r.components == 3) {
        for (size_t i = 0; i + 2 < v.size(); i += 3) {
          const glm::dvec3 n(v[i], v[i + 1], v[i + 2]);
          const double len = glm::length(n);
          normals.push_back(std::isfinite(len) && len > 0.0 ? glm::vec3(n / len) : glm::vec3(0.0f));
        }
        let_go(v);
        continue;
      }
      auto [it, fresh] = data_index.emplace(r.name, out.point_data.size());
      if (fresh) {
        if (k > 0)
          throw Error(
              fmt::format("{}: point data '{}' is not in every piece", piece_what, shown(r.name)));
        out.point_data.push_back({r.name, r.components, {}});
      }
      MeshPointData& d = out.point_data[it->second];
      if (d.components != r.components)
        throw Error(
            fmt::format("{}: point data '{}' changes its components", piece_what, shown(r.name)));
      if (d.values.empty())
        d.values = std::move(v);  // no second copy while both are held
      else
        d.values.insert(d.values.end(), v.begin(), v.end());
    }
    if (normals.size() == piece.points && (k == 0 || !out.mesh.normals.empty()))
      out.mesh.normals.insert(out.mesh.normals.end(), normals.begin(), normals.end());
    else
      out.mesh.normals.clear();
    base += piece.points;
  }
  for (const MeshPointData& d : out.point_data)
    if (d.values.size() != total_points * static_cast<uint64_t>(d.components))
      throw Error(fmt::format("{}: point data '{}' is not in every piece", what, shown(d.name)));
  if (out.mesh.normals.size() != out.mesh.positions.size()) out.mesh.normals.clear();
  for (const MeshPointData& d : out.line_data)
    if (d.values.size() != (out.lines.offsets.size() - 1) * static_cast<uint64_t>(d.components))
      throw Error(fmt::format("{}: cell data '{}' is not in every piece", what, shown(d.name)));
  // 3D Slicer's coordinate system: a String array SPACE in the field data.
  for (const ArrayRef& r : p.arrays)
    if (r.section == "FieldData" && r.name == "SPACE" && r.type == "String") {
      const std::vector<double> chars = decode(r, decoder, what, charge);
      const std::string space = first_string(chars);
      let_go(chars);
      if (space == "LPS" || space == "RAS")
        out.space = space == "RAS" ? MeshSpace::ras : MeshSpace::lps;
      else
        throw Error(fmt::format("{}: field SPACE is '{}', not LPS or RAS", what, shown(space)));
    }
  return out;
}

}  // namespace imx::detail
