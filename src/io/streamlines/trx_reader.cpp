// TRX reader: every array is checked against header.json's counts and the dtype its name gives
// before anything is allocated or inflated, then read in large pieces and converted in place.
#include <algorithm>
#include <bit>
#include <cctype>
#include <cerrno>
#include <cmath>
#include <cstring>
#include <fstream>
#include <map>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <system_error>
#include <vector>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "core/colour.hpp"
#include "intermix/error.hpp"
#include "intermix/limits.hpp"
#include "io/streamlines/trx.hpp"
#include "io/streams/input_file.hpp"
#include "io/streams/json_depth.hpp"
#include "io/streams/regular_file.hpp"
#include "io/streams/zip_archive.hpp"

namespace imx::detail {

namespace {

static_assert(std::endian::native == std::endian::little, "TRX arrays are little-endian");
static_assert(sizeof(glm::vec3) == 3 * sizeof(float), "points are read as packed floats");

constexpr size_t kPieceBytes = size_t{1} << 20;  // conversion buffer
constexpr uint64_t kMaxHeaderBytes = 1u << 20;   // header.json: a few hundred bytes in practice
constexpr int kMaxJsonDepth = 64;

// ---- dtypes, as the spec names them in file names ----

enum class Dtype { i8, i16, i32, i64, u8, u16, u32, u64, f16, f32, f64, bit };

struct DtypeName {
  std::string_view name;
  Dtype type;
  size_t bytes;
};

constexpr DtypeName kDtypes[] = {
    {"int8", Dtype::i8, 1},     {"int16", Dtype::i16, 2},   {"int32", Dtype::i32, 4},
    {"int64", Dtype::i64, 8},   {"uint8", Dtype::u8, 1},    {"uint16", Dtype::u16, 2},
    {"uint32", Dtype::u32, 4},  {"uint64", Dtype::u64, 8},  {"float16", Dtype::f16, 2},
    {"float32", Dtype::f32, 4}, {"float64", Dtype::f64, 8}, {"bit", Dtype::bit, 1}};

const DtypeName* find_dtype(std::string_view name) {
  for (const DtypeName& d : kDtypes)
    if (d.name == name) return &d;
  return nullptr;
}

bool is_float(Dtype t) {
  return t == Dtype::f16 || t == Dtype::f32 || t == Dtype::f64;
}

// IEEE half to float: every half value (subnormals, infinities, NaN) has an exact float.
float half_to_float(uint16_t h) {
  const uint32_t sign = static_cast<uint32_t>(h & 0x8000u) << 16;
  const uint32_t exponent = (h >> 10) & 0x1fu;
  const uint32_t mantissa = h & 0x3ffu;
  if (exponent == 0) {  // zero or subnormal: mantissa * 2^-24
    const float magnitude = std::ldexp(static_cast<float>(mantissa), -24);
    return sign != 0 ? -magnitude : magnitude;
  }
  const uint32_t bits = exponent == 0x1f ? sign | 0x7f800000u | (mantissa << 13)
                                         : sign | ((exponent + 112) << 23) | (mantissa << 13);
  return std::bit_cast<float>(bits);
}

template <class T>
void convert_as(const uint8_t* src, size_t n, float* dst) {
  for (size_t i = 0; i < n; ++i) {
    T v;
    std::memcpy(&v, src + i * sizeof(T), sizeof(T));
    dst[i] = static_cast<float>(v);
  }
}

void convert(Dtype type, const uint8_t* src, size_t n, float* dst) {
  switch (type) {
    case Dtype::i8:
      return convert_as<int8_t>(src, n, dst);
    case Dtype::i16:
      return convert_as<int16_t>(src, n, dst);
    case Dtype::i32:
      return convert_as<int32_t>(src, n, dst);
    case Dtype::i64:
      return convert_as<int64_t>(src, n, dst);
    case Dtype::u8:
      return convert_as<uint8_t>(src, n, dst);
    case Dtype::bit:
      return convert_as<uint8_t>(src, n, dst);
    case Dtype::u16:
      return convert_as<uint16_t>(src, n, dst);
    case Dtype::u32:
      return convert_as<uint32_t>(src, n, dst);
    case Dtype::u64:
      return convert_as<uint64_t>(src, n, dst);
    case Dtype::f32:
      return convert_as<float>(src, n, dst);
    case Dtype::f64:
      return convert_as<double>(src, n, dst);
    case Dtype::f16:
      for (size_t i = 0; i < n; ++i) {
        uint16_t h;
        std::memcpy(&h, src + 2 * i, 2);
        dst[i] = half_to_float(h);
      }
      return;
  }
}

// An integer element as a signed 64-bit value; uint64 values past INT64_MAX read as -1 (never
// a valid index or offset, so they are refused as such).
int64_t integer_at(Dtype type, const uint8_t* p) {
  auto get = [p]<class T>(T) {
    T v;
    std::memcpy(&v, p, sizeof(T));
    return v;
  };
  switch (type) {
    case Dtype::i8:
      return get(int8_t{});
    case Dtype::i16:
      return get(int16_t{});
    case Dtype::i32:
      return get(int32_t{});
    case Dtype::i64:
      return get(int64_t{});
    case Dtype::u8:
    case Dtype::bit:
      return get(uint8_t{});
    case Dtype::u16:
      return get(uint16_t{});
    case Dtype::u32:
      return get(uint32_t{});
    case Dtype::u64: {
      const uint64_t v = get(uint64_t{});
      return v > static_cast<uint64_t>(INT64_MAX) ? -1 : static_cast<int64_t>(v);
    }
    default:
      return -1;
  }
}

// ---- where the members' bytes come from: a zip archive or a folder ----

struct Member {
  std::string name;  // '/'-separated path inside the TRX
  uint64_t size = 0;
  size_t index = 0;  // the zip member, or the folder's file
};

class Source {
 public:
  virtual ~Source() = default;
  const std::vector<Member>& members() const { return members_; }
  // open(m), read() pieces holding exactly m.size bytes, finish(): as ZipArchive does.
  virtual void open(const Member& m) = 0;
  virtual void read(std::span<uint8_t> piece) = 0;
  virtual void finish() = 0;

 protected:
  std::vector<Member> members_;
};

class ZipSource final : public Source {
 public:
  ZipSource(const std::filesystem::path& file, const std::string& what) : zip_(file, what) {
    const std::vector<ZipMember>& all = zip_.members();
    for (size_t i = 0; i < all.size(); ++i)
      if (!all[i].directory) members_.push_back({all[i].name, all[i].size, i});
  }
  void open(const Member& m) override { zip_.open(m.index); }
  void read(std::span<uint8_t> piece) override { zip_.read(piece); }
  void finish() override { zip_.finish(); }

 private:
  ZipArchive zip_;
};

class FolderSource final : public Source {
 public:
  FolderSource(const std::filesystem::path& folder, std::string what)
      : folder_(folder), what_(std::move(what)) {
    // Only the spec's folders are listed: the top, dpv, dps, groups and dpg/GROUP.
    list("");
    for (const char* sub : {"dpv", "dps", "groups"}) list(sub);
    std::error_code ec;
    if (std::filesystem::is_directory(folder_ / "dpg", ec))
      for (const auto& e : std::filesystem::directory_iterator(folder_ / "dpg", ec))
        if (e.is_directory(ec)) list("dpg/" + e.path().filename().string());
    std::sort(members_.begin(), members_.end(),
              [](const Member& a, const Member& b) { return a.name < b.name; });
    for (size_t i = 0; i < members_.size(); ++i) members_[i].index = i;
  }

  void open(const Member& m) override {
    const std::filesystem::path file =
        resolve_data_file(folder_ / "header.json", m.name, "TRX member");
    in_ = open_input_stream(file,
                            fmt::format("{} (member '{}' of {})", file.string(), m.name, what_));
    member_ = &m;
    read_ = 0;
  }
  void read(std::span<uint8_t> piece) override {
    in_.read(reinterpret_cast<char*>(piece.data()), static_cast<std::streamsize>(piece.size()));
    if (static_cast<size_t>(in_.gcount()) != piece.size())
      throw Error(fmt::format("{}: member '{}' ends after {} of its {} bytes", what_, member_->name,
                              read_ + static_cast<uint64_t>(in_.gcount()), member_->size));
    read_ += piece.size();
  }
  void finish() override { in_.close(); }

 private:
  void list(const std::string& sub) {
    std::error_code ec;
    const std::filesystem::path dir = sub.empty() ? folder_ : folder_ / sub;
    if (!std::filesystem::is_directory(dir, ec)) return;
    for (const auto& e : std::filesystem::directory_iterator(dir, ec)) {
      if (e.is_directory(ec)) continue;
      const std::string name =
          sub.empty() ? e.path().filename().string() : sub + "/" + e.path().filename().string();
      const uint64_t size = e.is_regular_file(ec) ? e.file_size(ec) : 0;
      members_.push_back({name, ec ? 0 : size, 0});
    }
  }

  std::filesystem::path folder_;
  std::string what_;
  std::ifstream in_;
  const Member* member_ = nullptr;
  uint64_t read_ = 0;
};

// ---- the arrays a TRX holds ----

enum class Kind { positions, offsets, dpv, dps, group, dpg };

struct Array {
  const Member* member = nullptr;
  Kind kind = Kind::dpv;
  std::string base;   // the name before the dots
  std::string group;  // dpg: the group folder
  uint64_t columns = 1;
  const DtypeName* dtype = nullptr;
  uint64_t elements() const { return member->size / dtype->bytes; }
};

struct Header {
  uint64_t streamlines = 0;
  uint64_t vertices = 0;
};

class TrxReader {
 public:
  TrxReader(Source& source, std::string what, std::vector<std::string>& notes)
      : src_(source), what_(std::move(what)), notes_(notes) {}

  Streamlines read();

 private:
  [[noreturn]] void fail(const Member& m, const std::string& message) const {
    throw Error(fmt::format("{}: {}: {}", what_, m.name, message));
  }
  void classify();
  std::optional<Array> parse_name(const Member& m);
  void read_header();
  void check_sizes();
  void read_floats(const Array& a, std::span<float> out);
  std::vector<int64_t> read_integers(const Array& a);
  std::vector<uint64_t> read_offsets();
  std::vector<StreamlineValues> read_values(const Array& a, uint64_t rows);
  void read_groups(Streamlines& out);
  void read_colors(Streamlines& out);
  void drop_bad_streamlines(Streamlines& out, const std::vector<uint64_t>& offsets);

  Source& src_;
  std::string what_;
  std::vector<std::string>& notes_;
  const Member* header_member_ = nullptr;
  Header header_;
  std::optional<Array> positions_, offsets_;
  std::vector<Array> dpv_, dps_, groups_, dpg_;
  std::vector<std::string> ignored_;
};

std::optional<Array> TrxReader::parse_name(const Member& m) {
  std::vector<std::string> parts;
  for (size_t start = 0;;) {
    const size_t slash = m.name.find('/', start);
    parts.push_back(m.name.substr(start, slash == std::string::npos ? slash : slash - start));
    if (slash == std::string::npos) break;
    start = slash + 1;
  }
  const std::string& file = parts.back();
  if (file.size() > 5 && file.ends_with(".json")) return std::nullopt;  // e.g. dps/algo.json
  Array a;
  a.member = &m;
  if (parts.size() == 1) {
    if (file.starts_with("positions."))
      a.kind = Kind::positions;
    else if (file.starts_with("offsets."))
      a.kind = Kind::offsets;
    else
      return std::nullopt;
  } else if (parts.size() == 2 && parts[0] == "dpv") {
    a.kind = Kind::dpv;
  } else if (parts.size() == 2 && parts[0] == "dps") {
    a.kind = Kind::dps;
  } else if (parts.size() == 2 && parts[0] == "groups") {
    a.kind = Kind::group;
  } else if (parts.size() == 3 && parts[0] == "dpg") {
    a.kind = Kind::dpg;
    a.group = parts[1];
  } else {
    return std::nullopt;
  }
  std::vector<std::string> dots;
  for (size_t start = 0;;) {
    const size_t dot = file.find('.', start);
    dots.push_back(file.substr(start, dot == std::string::npos ? dot : dot - start));
    if (dot == std::string::npos) break;
    start = dot + 1;
  }
  a.dtype = find_dtype(dots.back());
  if (a.dtype == nullptr) return std::nullopt;  // not an array trx-python knows: ignored
  if ((dots.size() != 2 && dots.size() != 3) || dots[0].empty())
    fail(m, "an array's name must be NAME.DTYPE or NAME.COLUMNS.DTYPE, with no other dot");
  a.base = dots[0];
  if (dots.size() == 3) {
    const std::string& c = dots[1];
    if (c.empty() || c.size() > 9 ||
        !std::all_of(c.begin(), c.end(), [](unsigned char ch) { return std::isdigit(ch) != 0; }) ||
        std::stoull(c) == 0)
      fail(m, fmt::format("the column count '{}' in its name is not a positive integer", c));
    a.columns = std::stoull(c);
  }
  return a;
}

void TrxReader::classify() {
  std::map<std::string, const Member*> seen;  // kind/base: one array per name
  for (const Member& m : src_.members()) {
    if (m.name == "header.json") {
      if (header_member_ != nullptr) fail(m, "a second header.json");
      header_member_ = &m;
      continue;
    }
    std::optional<Array> a = parse_name(m);
    if (!a) {
      ignored_.push_back(m.name);
      continue;
    }
    const std::string key = fmt::format("{}/{}/{}", static_cast<int>(a->kind), a->group, a->base);
    if (const auto [it, fresh] = seen.emplace(key, &m); !fresh)
      fail(m,
           fmt::format("a second array named '{}' (the first is {})", a->base, it->second->name));
    switch (a->kind) {
      case Kind::positions:
        positions_ = a;
        break;
      case Kind::offsets:
        offsets_ = a;
        break;
      case Kind::dpv:
        dpv_.push_back(*a);
        break;
      case Kind::dps:
        dps_.push_back(*a);
        break;
      case Kind::group:
        groups_.push_back(*a);
        break;
      case Kind::dpg:
        dpg_.push_back(*a);
        break;
    }
  }
  if (header_member_ == nullptr) throw Error(fmt::format("{}: no header.json: not a TRX", what_));
  if (!positions_)
    throw Error(
        fmt::format("{}: no positions.3.DTYPE array: not a TRX (or not one it can read)", what_));
  if (!offsets_)
    throw Error(
        fmt::format("{}: no offsets.DTYPE array: not a TRX (or not one it can read)", what_));
}

bool nested_too_deep(std::string_view text) {
  return json_nested_deeper_than(text, kMaxJsonDepth);
}

void TrxReader::read_header() {
  const Member& m = *header_member_;
  if (m.size > kMaxHeaderBytes)
    fail(m, fmt::format("{} bytes, more than the {} a header may take", m.size, kMaxHeaderBytes));
  std::string text(static_cast<size_t>(m.size), '\0');
  src_.open(m);
  src_.read(std::span(reinterpret_cast<uint8_t*>(text.data()), text.size()));
  src_.finish();
  if (nested_too_deep(text)) fail(m, "JSON nested too deeply");
  nlohmann::json json;
  try {
    json = nlohmann::json::parse(text);
  } catch (const nlohmann::json::exception& e) {
    fail(m, fmt::format("not valid JSON ({})", e.what()));
  }
  if (!json.is_object()) fail(m, "not a JSON object");
  auto count = [&](const char* key) -> uint64_t {
    const auto it = json.find(key);
    if (it == json.end()) fail(m, fmt::format("no {} key", key));
    if (it->is_number_unsigned()) return it->get<uint64_t>();
    if (it->is_number_float()) {
      const double v = it->get<double>();
      if (v >= 0 && v < 1e18 && v == std::floor(v)) return static_cast<uint64_t>(v);
    }
    fail(m, fmt::format("{} is {}, not a count", key, it->dump()));
  };
  auto numbers = [&](const char* key, size_t rows, size_t columns) {
    const auto it = json.find(key);
    if (it == json.end()) fail(m, fmt::format("no {} key", key));
    std::vector<const nlohmann::json*> flat;
    if (it->is_array())
      for (const nlohmann::json& row : *it) {
        if (row.is_array() && columns > 1)
          for (const nlohmann::json& v : row) flat.push_back(&v);
        else
          flat.push_back(&row);
      }
    const bool ok = flat.size() == rows * columns &&
                    std::all_of(flat.begin(), flat.end(), [](const nlohmann::json* v) {
                      return v->is_number() && std::isfinite(v->get<double>());
                    });
    if (!ok)
      fail(m, fmt::format("{} must hold {} finite numbers{}", key, rows * columns,
                          rows > 1 ? fmt::format(" ({} lists of {})", rows, columns) : ""));
  };
  // The affine and grid describe the reference image; positions are RAS mm already.
  numbers("VOXEL_TO_RASMM", 4, 4);
  numbers("DIMENSIONS", 1, 3);
  header_.streamlines = count("NB_STREAMLINES");
  header_.vertices = count("NB_VERTICES");
  if (header_.vertices > UINT32_MAX)
    fail(m, fmt::format("NB_VERTICES is {}: more than the {} points intermix can index",
                        header_.vertices, UINT32_MAX));
  if (header_.streamlines >= UINT32_MAX)
    fail(m, fmt::format("NB_STREAMLINES is {}: more than intermix can index", header_.streamlines));
}

// Every array's byte size against the header's counts and its dtype, before reading any.
void TrxReader::check_sizes() {
  const uint64_t n = header_.streamlines, v = header_.vertices;
  auto expect = [&](const Array& a, uint64_t elements, const std::string& counts) {
    if (a.member->size % a.dtype->bytes != 0 || a.member->size / a.dtype->bytes != elements)
      fail(*a.member, fmt::format("{} bytes, but {} needs {} {} values ({} bytes)", a.member->size,
                                  counts, elements, a.dtype->name, elements * a.dtype->bytes));
  };
  const Array& p = *positions_;
  if (p.columns != 3) fail(*p.member, "positions must have 3 columns (positions.3.DTYPE)");
  if (!is_float(p.dtype->type))
    fail(*p.member, fmt::format("positions of dtype {}: only float16, float32 and float64 are "
                                "supported",
                                p.dtype->name));
  expect(p, v * 3, fmt::format("NB_VERTICES = {} x 3", v));
  const Array& o = *offsets_;
  if (o.columns != 1) fail(*o.member, "offsets must have 1 column");
  if (is_float(o.dtype->type) || o.dtype->type == Dtype::bit)
    fail(*o.member, fmt::format("offsets of dtype {}: they must be integers (uint32 or uint64)",
                                o.dtype->name));
  if (o.member->size != n * o.dtype->bytes)
    expect(o, n + 1, fmt::format("NB_STREAMLINES = {} (+ 1)", n));
  // Data arrays are optional: one whose size disagrees with the counts (NiiVue's dpsv.trx holds
  // one value more than its streamlines) is left out with a note, the geometry is still whole.
  auto drop_mismatched = [&](std::vector<Array>& arrays, uint64_t rows, const char* count) {
    std::erase_if(arrays, [&](const Array& a) {
      const uint64_t elements = rows * a.columns;
      if (a.member->size % a.dtype->bytes == 0 && a.member->size / a.dtype->bytes == elements)
        return false;
      notes_.push_back(fmt::format(
          "{} left out: {} bytes, but {} = {} x {} columns needs {} {} "
          "values",
          a.member->name, a.member->size, count, rows, a.columns, elements, a.dtype->name));
      return true;
    });
  };
  drop_mismatched(dpv_, v, "NB_VERTICES");
  drop_mismatched(dps_, n, "NB_STREAMLINES");
  for (const Array& a : groups_) {
    if (a.columns != 1) fail(*a.member, "a group must have 1 column (streamline indices)");
    if (is_float(a.dtype->type))
      fail(*a.member,
           fmt::format("group indices of dtype {}: they must be integers", a.dtype->name));
    if (a.member->size % a.dtype->bytes != 0)
      fail(*a.member,
           fmt::format("{} bytes: not a whole number of {} values", a.member->size, a.dtype->name));
  }
  for (const Array& a : dpg_) expect(a, a.columns, fmt::format("its {} columns", a.columns));

  // Memory: the points, the offsets (read as 64-bit), and every array as floats.
  uint64_t bytes = v * sizeof(glm::vec3) + (n + 1) * (8 + 4);
  for (const Array& a : dpv_) bytes += v * a.columns * 4 * (a.columns > 1 ? 2 : 1);
  for (const Array& a : dps_) bytes += n * a.columns * 4 * (a.columns > 1 ? 2 : 1);
  for (const Array& a : groups_) bytes += a.elements() * (8 + 4);
  check_memory(bytes, what_);
}

void TrxReader::read_floats(const Array& a, std::span<float> out) {
  src_.open(*a.member);
  if (a.dtype->type == Dtype::f32) {
    src_.read(std::span(reinterpret_cast<uint8_t*>(out.data()), out.size_bytes()));
  } else {
    const size_t per_piece = kPieceBytes / a.dtype->bytes;
    std::vector<uint8_t> piece(std::min(out.size(), per_piece) * a.dtype->bytes);
    for (size_t i = 0; i < out.size(); i += per_piece) {
      const size_t n = std::min(out.size() - i, per_piece);
      src_.read(std::span(piece).first(n * a.dtype->bytes));
      convert(a.dtype->type, piece.data(), n, out.data() + i);
    }
  }
  src_.finish();
}

std::vector<int64_t> TrxReader::read_integers(const Array& a) {
  std::vector<int64_t> out(static_cast<size_t>(a.elements()));
  const size_t per_piece = kPieceBytes / a.dtype->bytes;
  std::vector<uint8_t> piece(std::min(out.size(), per_piece) * a.dtype->bytes);
  src_.open(*a.member);
  for (size_t i = 0; i < out.size(); i += per_piece) {
    const size_t n = std::min(out.size() - i, per_piece);
    src_.read(std::span(piece).first(n * a.dtype->bytes));
    for (size_t k = 0; k < n; ++k)
      out[i + k] = integer_at(a.dtype->type, piece.data() + k * a.dtype->bytes);
  }
  src_.finish();
  return out;
}

// NB_STREAMLINES + 1 offsets (the spec's form, ending at NB_VERTICES), or NB_STREAMLINES (older
// writers): both checked to start at 0 and ascend within NB_VERTICES.
std::vector<uint64_t> TrxReader::read_offsets() {
  const Array& a = *offsets_;
  const std::vector<int64_t> raw = read_integers(a);
  const uint64_t n = header_.streamlines, v = header_.vertices;
  std::vector<uint64_t> offsets(static_cast<size_t>(n) + 1, v);
  for (size_t i = 0; i < raw.size(); ++i) {
    if (raw[i] < 0 || static_cast<uint64_t>(raw[i]) > v)
      fail(*a.member,
           fmt::format("offset {} is {}, outside 0 .. NB_VERTICES = {}", i,
                       raw[i] < 0 && a.dtype->type == Dtype::u64 ? std::string("past 2^63")
                                                                 : std::to_string(raw[i]),
                       v));
    if (i > 0 && raw[i] < raw[i - 1])
      fail(*a.member, fmt::format("offsets do not ascend: offset {} is {}, offset {} is {}", i - 1,
                                  raw[i - 1], i, raw[i]));
    offsets[i] = static_cast<uint64_t>(raw[i]);
  }
  if (!raw.empty() && raw[0] != 0)
    fail(*a.member, fmt::format("the first offset is {}, not 0", raw[0]));
  if (offsets[n] < v)  // as trx-python reads it: the streamlines end at the last offset
    notes_.push_back(
        fmt::format("{}: the last offset is {}: the last {} vertex(es) of "
                    "NB_VERTICES = {} belong to no streamline, ignored",
                    what_, offsets[n], v - offsets[n], v));
  if (n == 0 && v != 0) fail(*a.member, fmt::format("no streamlines, but NB_VERTICES is {}", v));
  return offsets;
}

std::vector<StreamlineValues> TrxReader::read_values(const Array& a, uint64_t rows) {
  std::vector<StreamlineValues> out;
  if (a.columns == 1) {
    StreamlineValues one{a.base, std::vector<float>(static_cast<size_t>(rows))};
    read_floats(a, one.values);
    out.push_back(std::move(one));
    return out;
  }
  std::vector<float> all(static_cast<size_t>(rows * a.columns));
  read_floats(a, all);
  for (uint64_t c = 0; c < a.columns; ++c) {
    StreamlineValues column{fmt::format("{}_{}", a.base, c),
                            std::vector<float>(static_cast<size_t>(rows))};
    for (uint64_t r = 0; r < rows; ++r) column.values[r] = all[r * a.columns + c];
    out.push_back(std::move(column));
  }
  return out;
}

void TrxReader::read_groups(Streamlines& out) {
  for (const Array& a : groups_) {
    const std::vector<int64_t> raw = read_integers(a);
    StreamlineGroup g;
    g.name = a.base;
    g.members.reserve(raw.size());
    for (size_t i = 0; i < raw.size(); ++i) {
      if (raw[i] < 0 || static_cast<uint64_t>(raw[i]) >= header_.streamlines)
        fail(*a.member,
             fmt::format("member {} is streamline {}, outside 0 .. NB_STREAMLINES - 1 "
                         "= {}",
                         i, raw[i] < 0 ? std::string("< 0 or past 2^63") : std::to_string(raw[i]),
                         static_cast<int64_t>(header_.streamlines) - 1));
      g.members.push_back(static_cast<uint32_t>(raw[i]));
    }
    if (!std::is_sorted(g.members.begin(), g.members.end()) ||
        std::adjacent_find(g.members.begin(), g.members.end()) != g.members.end()) {
      std::sort(g.members.begin(), g.members.end());
      g.members.erase(std::unique(g.members.begin(), g.members.end()), g.members.end());
      notes_.push_back(
          fmt::format("{}: group '{}': its indices are sorted, once each", what_, g.name));
    }
    out.groups.push_back(std::move(g));
  }
}

bool names_a_colour(const std::string& name) {
  std::string lower = name;
  for (char& c : lower) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return lower.find("color") != std::string::npos || lower.find("colour") != std::string::npos;
}

// dpg: a group's colour from its first *colo(u)r*.3.DTYPE array; other per-group data is
// ignored with a note (as is a colour outside 0..255).
void TrxReader::read_colors(Streamlines& out) {
  std::vector<std::string> unused;
  for (const Array& a : dpg_) {
    const auto g = std::find_if(out.groups.begin(), out.groups.end(),
                                [&](const StreamlineGroup& s) { return s.name == a.group; });
    if (g == out.groups.end())
      fail(*a.member, fmt::format("data for group '{}', which groups/ does not declare", a.group));
    if (g->color || a.columns != 3 || !names_a_colour(a.base)) {
      unused.push_back(a.member->name);
      continue;
    }
    float rgb[3];
    read_floats(a, rgb);
    const bool finite = std::all_of(rgb, rgb + 3, [](float c) { return std::isfinite(c); });
    const float top = std::max({rgb[0], rgb[1], rgb[2]});
    const float bottom = std::min({rgb[0], rgb[1], rgb[2]});
    if (!finite || bottom < 0 || top > 255) {
      notes_.push_back(fmt::format("{}: {}: ({}, {}, {}) is no colour (0..1 or 0..255): ignored",
                                   what_, a.member->name, rgb[0], rgb[1], rgb[2]));
      continue;
    }
    // Integer colours are bytes; float colours are 0..1 unless a value says bytes.
    const float scale = (!is_float(a.dtype->type) || top > 1.0f) ? 1.0f / 255.0f : 1.0f;
    g->color = display_to_linear(glm::vec3(rgb[0], rgb[1], rgb[2]) * scale);  // a display colour
  }
  if (!unused.empty())
    notes_.push_back(
        fmt::format("{}: per-group data not shown: {}", what_, fmt::join(unused, ", ")));
}

// Drops the streamlines with fewer than 2 points or a non-finite coordinate, compacting the
// points, every per-point and per-streamline array and the groups' indices.
void TrxReader::drop_bad_streamlines(Streamlines& out, const std::vector<uint64_t>& offsets) {
  const size_t n = offsets.size() - 1;
  std::vector<uint8_t> keep(n, 1);
  size_t short_ones = 0, non_finite = 0;
  for (size_t i = 0; i < n; ++i) {
    if (offsets[i + 1] - offsets[i] < 2) {
      keep[i] = 0;
      ++short_ones;
      continue;
    }
    for (uint64_t k = offsets[i]; k < offsets[i + 1]; ++k) {
      const glm::vec3& p = out.points[k];
      if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z)) {
        keep[i] = 0;
        ++non_finite;
        break;
      }
    }
  }
  out.offsets.assign(1, 0);
  out.offsets.reserve(n + 1);
  if (short_ones + non_finite == 0) {
    for (size_t i = 0; i < n; ++i) out.offsets.push_back(static_cast<uint32_t>(offsets[i + 1]));
    out.points.resize(out.offsets.back());  // vertices past the last offset: in no streamline
    for (StreamlineValues& v : out.point_values) v.values.resize(out.offsets.back());
    return;
  }
  if (short_ones > 0)
    notes_.push_back(
        fmt::format("{}: {} streamline(s) with fewer than 2 points dropped", what_, short_ones));
  if (non_finite > 0)
    notes_.push_back(
        fmt::format("{}: {} streamline(s) with NaN or infinite points dropped", what_, non_finite));
  auto compact_points = [&](auto& values) {  // values: one entry per point, in place
    size_t to = 0;
    for (size_t i = 0; i < n; ++i) {
      if (!keep[i]) continue;
      for (uint64_t k = offsets[i]; k < offsets[i + 1]; ++k) values[to++] = values[k];
    }
    values.resize(to);
  };
  compact_points(out.points);
  for (StreamlineValues& v : out.point_values) compact_points(v.values);
  for (StreamlineValues& v : out.streamline_values) {
    size_t to = 0;
    for (size_t i = 0; i < n; ++i)
      if (keep[i]) v.values[to++] = v.values[i];
    v.values.resize(to);
  }
  std::vector<uint32_t> new_index(n, UINT32_MAX);
  for (size_t i = 0; i < n; ++i) {
    if (!keep[i]) continue;
    new_index[i] = static_cast<uint32_t>(out.offsets.size() - 1);
    out.offsets.push_back(out.offsets.back() + static_cast<uint32_t>(offsets[i + 1] - offsets[i]));
  }
  for (StreamlineGroup& g : out.groups) {
    size_t to = 0;
    for (uint32_t m : g.members)
      if (new_index[m] != UINT32_MAX) g.members[to++] = new_index[m];
    g.members.resize(to);
  }
}

Streamlines TrxReader::read() {
  classify();
  read_header();
  check_sizes();
  if (!ignored_.empty())
    notes_.push_back(
        fmt::format("{}: not TRX arrays, ignored: {}", what_, fmt::join(ignored_, ", ")));

  Streamlines out;
  out.points.resize(static_cast<size_t>(header_.vertices));
  read_floats(*positions_,
              std::span(reinterpret_cast<float*>(out.points.data()), out.points.size() * 3));
  for (glm::vec3& p : out.points) {  // RAS -> LPS
    p.x = -p.x;
    p.y = -p.y;
  }
  const std::vector<uint64_t> offsets = read_offsets();
  for (const Array& a : dpv_)
    for (StreamlineValues& v : read_values(a, header_.vertices))
      out.point_values.push_back(std::move(v));
  for (const Array& a : dps_)
    for (StreamlineValues& v : read_values(a, header_.streamlines))
      out.streamline_values.push_back(std::move(v));
  read_groups(out);
  read_colors(out);
  drop_bad_streamlines(out, offsets);
  return out;
}

}  // namespace

Streamlines read_trx(const std::filesystem::path& file, std::vector<std::string>& notes) {
  const std::string what = file.string();
  std::error_code ec;
  std::unique_ptr<Source> source;
  if (std::filesystem::is_directory(file, ec)) {
    require_regular_file(file / "header.json", fmt::format("{} (TRX folder header)", what));
    source = std::make_unique<FolderSource>(file, what);
  } else {
    source = std::make_unique<ZipSource>(file, what);
  }
  try {
    return TrxReader(*source, what, notes).read();
  } catch (const std::bad_alloc&) {
    throw OutOfMemory(out_of_memory_message(what));
  }
}

}  // namespace imx::detail
