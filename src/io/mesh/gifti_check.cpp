#include "io/mesh/gifti_check.hpp"

#include <expat.h>
#include <zlib.h>

#include <algorithm>
#include <array>
#include <bit>
#include <cfloat>
#include <charconv>
#include <cmath>
#include <cstring>
#include <fstream>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <type_traits>
#include <utility>
#include <vector>

#include <fmt/format.h>
#include <fmt/ranges.h>

#include "intermix/error.hpp"
#include "intermix/limits.hpp"
#include "io/streams/base64.hpp"
#include "io/streams/gzip.hpp"
#include "io/streams/header_text.hpp"
#include "io/streams/input_file.hpp"
#include "io/streams/xml_parser.hpp"

namespace imx::detail {
namespace {

// One array's largest size (its rows must also count in uint32 for triangles' indices).
constexpr uint64_t kMaxArrayBytes = uint64_t{1} << 30;
constexpr size_t kMaxToken = 64;  // one ASCII number

enum class Encoding { ascii, base64, gzip_base64 };
enum class Kind { floating, integer };

struct TypeInfo {
  const char* name;
  int bytes;
  Kind kind;
  GiftiType type;
};

// The data types intermix reads, by their GIfTI names.
const std::map<std::string, TypeInfo, std::less<>>& types() {
  static const std::map<std::string, TypeInfo, std::less<>> table = {
      {"NIFTI_TYPE_FLOAT32", {"float32", 4, Kind::floating, GiftiType::float32}},
      {"NIFTI_TYPE_FLOAT64", {"float64", 8, Kind::floating, GiftiType::float64}},
      {"NIFTI_TYPE_INT8", {"int8", 1, Kind::integer, GiftiType::int8}},
      {"NIFTI_TYPE_UINT8", {"uint8", 1, Kind::integer, GiftiType::uint8}},
      {"NIFTI_TYPE_INT16", {"int16", 2, Kind::integer, GiftiType::int16}},
      {"NIFTI_TYPE_UINT16", {"uint16", 2, Kind::integer, GiftiType::uint16}},
      {"NIFTI_TYPE_INT32", {"int32", 4, Kind::integer, GiftiType::int32}},
      {"NIFTI_TYPE_UINT32", {"uint32", 4, Kind::integer, GiftiType::uint32}},
      {"NIFTI_TYPE_INT64", {"int64", 8, Kind::integer, GiftiType::int64}},
      {"NIFTI_TYPE_UINT64", {"uint64", 8, Kind::integer, GiftiType::uint64}},
  };
  return table;
}

// The encodings by every name nibabel knows them (the GIfTI spelling, its own label and the
// GIFTI_ENCODING_ constant): older files say B64BIN. External data is not among them.
std::optional<Encoding> encoding_named(std::string_view name) {
  if (name == "ASCII" || name == "GIFTI_ENCODING_ASCII") return Encoding::ascii;
  if (name == "Base64Binary" || name == "B64BIN" || name == "GIFTI_ENCODING_B64BIN")
    return Encoding::base64;
  if (name == "GZipBase64Binary" || name == "B64GZ" || name == "GIFTI_ENCODING_B64GZ")
    return Encoding::gzip_base64;
  return std::nullopt;
}

// Whether the byte order is big-endian, by nibabel's names for the two (an undefined one is not
// a byte order).
std::optional<bool> endian_named(std::string_view name) {
  if (name == "BigEndian" || name == "GIFTI_ENDIAN_BIG") return true;
  if (name == "LittleEndian" || name == "GIFTI_ENDIAN_LITTLE") return false;
  return std::nullopt;
}

// Decodes the <Data> text of one checked array chunk by chunk, counting what it holds and
// appending the bytes to `keep` when given (ASCII values as this machine stores their type).
// Compressed data is inflated only when kept: otherwise its size need only be possible.
class DataDecoder {
 public:
  DataDecoder(std::string what, Encoding encoding, const TypeInfo& type, uint64_t values,
              uint64_t bytes, std::vector<uint8_t>* keep)
      : what_(std::move(what)),
        encoding_(encoding),
        type_(type),
        values_(values),
        bytes_(bytes),
        keep_(keep) {
    if (encoding_ == Encoding::gzip_base64 && keep_) {
      stream_ = z_stream{};
      if (inflateInit(&stream_) != Z_OK) throw Error("zlib cannot start inflating");
      inflating_ = true;
    }
  }
  ~DataDecoder() {
    if (inflating_) inflateEnd(&stream_);
  }
  DataDecoder(const DataDecoder&) = delete;
  DataDecoder& operator=(const DataDecoder&) = delete;

  // An empty string, or why the text is not the claimed data.
  std::string add(std::string_view text) {
    if (!fault_.empty()) return fault_;
    if (encoding_ == Encoding::ascii) {
      for (char c : text) {
        if (std::isspace(static_cast<unsigned char>(c))) {
          end_token();
          if (c == '\n') end_line();
        } else if (token_.size() == kMaxToken) {
          fault_ = fmt::format("value {} is not a number", count_ + 1);
        } else {
          token_ += c;
        }
        if (!fault_.empty()) return fault_;
      }
      return fault_;
    }
    for (unsigned char c : text) {
      if (std::isspace(c)) continue;
      if (c == '=') {
        padded_ = true;
        continue;
      }
      const int v = base64_value(c);
      if (v < 0 || padded_) return fault_ = "the base64 data holds a character that is not base64";
      quad_ = (quad_ << 6) | static_cast<uint32_t>(v);
      if (++quad_chars_ == 4) {
        const uint8_t out[3] = {static_cast<uint8_t>(quad_ >> 16), static_cast<uint8_t>(quad_ >> 8),
                                static_cast<uint8_t>(quad_)};
        emit(out, 3);
        quad_ = 0;
        quad_chars_ = 0;
      }
      if (!fault_.empty()) return fault_;
    }
    return fault_;
  }

  // At </Data>: an empty string, or why the data does not match the claim.
  std::string finish() {
    if (!fault_.empty()) return fault_;
    if (encoding_ == Encoding::ascii) {
      end_token();
      end_line();
      if (fault_.empty() && count_ != values_)
        fault_ = fmt::format("the data holds {} values, the dimensions claim {}", count_, values_);
      return fault_;
    }
    // A final group of 2 or 3 characters carries 1 or 2 bytes.
    if (quad_chars_ == 1) return fault_ = "the base64 data ends in the middle of a byte";
    if (quad_chars_ > 1) {
      const uint32_t q = quad_ << (6 * (4 - quad_chars_));
      const uint8_t out[2] = {static_cast<uint8_t>(q >> 16), static_cast<uint8_t>(q >> 8)};
      emit(out, quad_chars_ - 1);
      if (!fault_.empty()) return fault_;
    }
    if (encoding_ == Encoding::gzip_base64) {
      if (!keep_) {  // not inflated: its size need only be possible
        check_inflatable(bytes_, decoded_, what_);
        return fault_;
      }
      if (!ended_) return fault_ = "the compressed data is truncated";
      if (inflated_ != bytes_)
        return fault_ = fmt::format("the data inflates to {} bytes, the dimensions claim {}",
                                    inflated_, bytes_);
    } else if (decoded_ != bytes_) {
      return fault_ = fmt::format("the data decodes to {} bytes, the dimensions claim {}", decoded_,
                                  bytes_);
    }
    return fault_;
  }

  // ASCII data's lines: how many hold values, and how many each holds where all hold as many.
  struct Lines {
    uint64_t count = 0, width = 0;
    bool uniform = true;
  };
  const Lines& lines() const { return lines_; }

 private:
  void end_line() {
    if (line_values_ == 0) return;
    if (++lines_.count == 1)
      lines_.width = line_values_;
    else if (lines_.width != line_values_)
      lines_.uniform = false;
    line_values_ = 0;
  }

  void keep(const uint8_t* data, size_t n) {
    if (keep_) keep_->insert(keep_->end(), data, data + n);
  }

  void end_token() {
    if (token_.empty()) return;
    ++count_;
    ++line_values_;
    if (count_ > values_) {
      fault_ = fmt::format("the data holds more values than the {} the dimensions claim", values_);
      return;
    }
    const char* b = token_.data();
    const char* e = b + token_.size();
    if (*b == '+') ++b;
    const bool ok = visit_gifti_type(type_.type, [&]<class T>(T value) {
      if constexpr (std::is_same_v<T, float>) {  // as a double: tiny values round to 0
        double d;
        auto r = std::from_chars(b, e, d);
        if (r.ec != std::errc() || r.ptr != e || !(std::abs(d) <= FLT_MAX)) return false;
        value = static_cast<float>(d);
      } else {
        auto r = std::from_chars(b, e, value);
        if (r.ec != std::errc() || r.ptr != e) return false;
      }
      keep(reinterpret_cast<const uint8_t*>(&value), sizeof value);
      return true;
    });
    if (!ok)
      fault_ = fmt::format("value {} '{}' is not {}", count_, shown(token_),
                           type_.kind == Kind::floating
                               ? fmt::format("a {} number", type_.name)
                               : fmt::format("an integer within {}'s range", type_.name));
    token_.clear();
  }

  void emit(const uint8_t* data, int n) {
    decoded_ += static_cast<uint64_t>(n);
    if (encoding_ == Encoding::base64) {
      if (decoded_ > bytes_)
        fault_ = fmt::format("the data holds more than {} bytes", bytes_);
      else
        keep(data, static_cast<size_t>(n));
      return;
    }
    if (!keep_ || ended_) return;  // bytes after the stream are ignored
    stream_.next_in = const_cast<Bytef*>(data);
    stream_.avail_in = static_cast<uInt>(n);
    while (stream_.avail_in > 0 && !ended_) {
      // Never more than one byte past the claim, which is then refused.
      const auto room =
          static_cast<size_t>(std::min<uint64_t>(scratch_.size(), bytes_ - inflated_ + 1));
      stream_.next_out = scratch_.data();
      stream_.avail_out = static_cast<uInt>(room);
      const int rc = inflate(&stream_, Z_NO_FLUSH);
      const size_t produced = room - stream_.avail_out;
      inflated_ += produced;
      if (inflated_ > bytes_) {
        fault_ =
            fmt::format("the data inflates to more than the {} bytes the dimensions claim", bytes_);
        return;
      }
      keep(scratch_.data(), produced);
      if (rc == Z_STREAM_END)
        ended_ = true;
      else if (rc != Z_OK && rc != Z_BUF_ERROR) {
        fault_ = "the compressed data is corrupt";
        return;
      }
    }
  }

  std::string what_;
  Encoding encoding_;
  TypeInfo type_;
  uint64_t values_, bytes_;
  std::vector<uint8_t>* keep_;
  std::string fault_;
  // ASCII
  std::string token_;
  uint64_t count_ = 0;
  uint64_t line_values_ = 0;  // on the line being read
  Lines lines_;
  // base64
  uint32_t quad_ = 0;
  int quad_chars_ = 0;
  bool padded_ = false;
  uint64_t decoded_ = 0;
  // zlib
  z_stream stream_{};
  bool inflating_ = false, ended_ = false;
  uint64_t inflated_ = 0;
  std::array<Bytef, 1 << 16> scratch_{};
};

// The parent each GIfTI element must have (GIFTI itself is the root): other readers trust the
// nesting (libgiftiio wrote before its arrays for a <Name> under the wrong parent).
const std::map<std::string, std::string, std::less<>>& parents() {
  static const std::map<std::string, std::string, std::less<>> table = {
      {"MetaData", "GIFTI|DataArray"},
      {"MD", "MetaData"},
      {"Name", "MD"},
      {"Value", "MD"},
      {"LabelTable", "GIFTI"},
      {"Label", "LabelTable"},
      {"DataArray", "GIFTI"},
      {"CoordinateSystemTransformMatrix", "DataArray"},
      {"Data", "DataArray"},
      {"DataSpace", "CoordinateSystemTransformMatrix"},
      {"TransformedSpace", "CoordinateSystemTransformMatrix"},
      {"MatrixData", "CoordinateSystemTransformMatrix"},
  };
  return table;
}

bool parent_allowed(std::string_view allowed, std::string_view parent) {
  while (!allowed.empty()) {
    const size_t bar = allowed.find('|');
    if (allowed.substr(0, bar) == parent) return true;
    allowed = bar == std::string_view::npos ? std::string_view() : allowed.substr(bar + 1);
  }
  return false;
}

struct Parser {
  std::filesystem::path file;
  uint64_t file_size = 0;
  XML_Parser xml = nullptr;
  std::string fault;
  int depth = 0;
  std::vector<std::string> stack;    // open elements
  int arrays = 0;                    // DataArray elements seen
  std::string claimed_arrays;        // the GIFTI element's NumberOfDataArrays
  int checked = -1;                  // the array being checked, or -1
  int data_depth = 0;                // depth of the checked array's <Data>, or 0
  bool has_data = false;             // the checked array had a <Data> element
  int pointset = -1, triangle = -1;  // the arrays kept, by their order in the file
  GiftiSurface surface;
  // Overlay mode: the data array of values kept (wanted, or the first that fits with -1).
  bool overlay_mode = false;
  int wanted = -1;
  GiftiOverlay overlay;
  bool sparse = false;                     // a NIFTI_INTENT_NODE_INDEX array
  std::vector<std::string> value_intents;  // of the arrays of per-vertex values, for messages
  std::optional<GiftiLabel> label;         // the <Label> being read
  uint64_t kept_bytes = 0;                 // the kept arrays and the mesh made of them
  // The checked array's claim, until its <Data>.
  Encoding encoding = Encoding::ascii;
  TypeInfo type{};
  uint64_t values = 0, bytes = 0;
  GiftiArray* kept = nullptr;
  std::optional<DataDecoder> decoder;

  void fail(std::string message) {
    if (fault.empty()) fault = std::move(message);
    XML_StopParser(xml, XML_FALSE);
  }

  std::string where() const { return fmt::format("data array {}", checked); }

  // Every array's claim; the surface's two also need the shape and types of vertices and
  // triangles.
  void start_array(const char** attrs) {
    const int index = arrays++;
    std::map<std::string, std::string, std::less<>> a;
    for (const char** p = attrs; p[0] && p[1]; p += 2) a[p[0]] = p[1];
    auto get = [&](std::string_view key) {
      auto it = a.find(key);
      return it == a.end() ? std::string() : it->second;
    };
    const std::string intent = get("Intent");
    const bool is_pointset = !overlay_mode && intent == "NIFTI_INTENT_POINTSET" && pointset < 0;
    const bool is_triangle = !overlay_mode && intent == "NIFTI_INTENT_TRIANGLE" && triangle < 0;
    if (intent == "NIFTI_INTENT_NODE_INDEX") sparse = true;
    const bool values_intent = intent != "NIFTI_INTENT_POINTSET" &&
                               intent != "NIFTI_INTENT_TRIANGLE" && intent != "NIFTI_INTENT_VECTOR";
    if (values_intent && value_intents.size() < 8)
      value_intents.push_back(intent.empty() ? "no Intent" : shown(intent));
    const bool is_overlay =
        overlay_mode && overlay.index < 0 && (wanted >= 0 ? index == wanted : values_intent);
    checked = index;
    has_data = false;
    kept = nullptr;
    if (is_pointset) pointset = index;
    if (is_triangle) triangle = index;
    const std::string what = fmt::format("data array {} ({})", index, shown(intent));

    const std::string external = get("ExternalFileName");
    if (!external.empty())
      return fail(fmt::format("{}: external data files (ExternalFileName '{}') are not read", what,
                              shown(external)));
    const std::string encoding_name = get("Encoding");
    if (const std::optional<Encoding> e = encoding_named(encoding_name))
      encoding = *e;
    else
      return fail(fmt::format("{}: Encoding '{}' is not ASCII, Base64Binary or GZipBase64Binary",
                              what, shown(encoding_name)));
    const std::optional<bool> big_endian = endian_named(get("Endian"));
    if (encoding != Encoding::ascii && !big_endian)
      return fail(fmt::format("{}: Endian '{}' is not LittleEndian or BigEndian", what,
                              shown(get("Endian"))));
    const std::string order = get("ArrayIndexingOrder");
    if (order != "RowMajorOrder" && order != "ColumnMajorOrder")
      return fail(
          fmt::format("{}: ArrayIndexingOrder '{}' is not RowMajorOrder or ColumnMajorOrder", what,
                      shown(order)));
    const std::string type_name = get("DataType");
    auto known = types().find(type_name);
    if (known == types().end())
      return fail(
          fmt::format("{}: DataType '{}' is not a type intermix reads", what, shown(type_name)));
    const TypeInfo& t = type = known->second;

    const std::string dimensionality = get("Dimensionality");
    int n_dims = 0;
    auto r = std::from_chars(dimensionality.data(), dimensionality.data() + dimensionality.size(),
                             n_dims);
    if (r.ec != std::errc() || r.ptr != dimensionality.data() + dimensionality.size() ||
        n_dims < 1 || n_dims > 6)
      return fail(
          fmt::format("{}: Dimensionality '{}' is not 1 to 6", what, shown(dimensionality)));
    int dims[6] = {0, 0, 0, 0, 0, 0};
    values = 1;
    for (int k = 0; k < n_dims; ++k) {
      const std::string d = get(fmt::format("Dim{}", k));
      auto rd = std::from_chars(d.data(), d.data() + d.size(), dims[k]);
      if (rd.ec != std::errc() || rd.ptr != d.data() + d.size() || d.empty() || dims[k] <= 0)
        return fail(fmt::format("{}: Dim{} '{}' is not a positive integer", what, k, shown(d)));
      values *= static_cast<uint64_t>(dims[k]);  // at most 2^31 per factor, checked each time
      if (values > kMaxArrayBytes)
        return fail(
            fmt::format("{}: its dimensions claim more than {} values", what, kMaxArrayBytes));
    }
    bytes = values * static_cast<uint64_t>(t.bytes);
    if (bytes > kMaxArrayBytes)
      return fail(fmt::format("{}: {} {} values ({}) are more than intermix reads ({})", what,
                              values, t.name, format_bytes(bytes), format_bytes(kMaxArrayBytes)));

    if (is_pointset || is_triangle) {
      if (is_pointset && t.kind != Kind::floating)
        return fail(fmt::format("{}: DataType {} is not float32 or float64", what, t.name));
      if (is_triangle && t.kind != Kind::integer)
        return fail(fmt::format("{}: DataType {} is not an integer type", what, t.name));
      if (n_dims != 2)
        return fail(fmt::format("{}: Dimensionality {} is not 2 (one row of 3 per {})", what,
                                n_dims, is_pointset ? "vertex" : "triangle"));
      if (dims[1] != 3)
        return fail(fmt::format("{}: Dim1 is {}, not 3 ({} per row)", what, dims[1],
                                is_pointset ? "x, y, z" : "three vertex indices"));
      // Both arrays as stored and the mesh's vertices or triangles (12 bytes a row) at once.
      kept_bytes += bytes + 12 * static_cast<uint64_t>(dims[0]);
      check_memory(kept_bytes, fmt::format("{}: {} rows of 3 {} values and the mesh made of them",
                                           what, dims[0], t.name));
      kept = is_pointset ? &surface.points : &surface.triangles;
      kept->type = t.type;
      kept->rows = static_cast<uint64_t>(dims[0]);
      kept->column_major = order == "ColumnMajorOrder";
      kept->swapped =
          encoding != Encoding::ascii && *big_endian != (std::endian::native == std::endian::big);
    }
    if (is_overlay) {
      if (n_dims > 2 || (n_dims == 2 && dims[1] != 1))
        return fail(fmt::format("{}: Dimensionality {} (Dim1 {}) is not one value per vertex", what,
                                n_dims, n_dims == 2 ? dims[1] : 0));
      kept_bytes += bytes + 8 * static_cast<uint64_t>(dims[0]);
      check_memory(kept_bytes, fmt::format("{}: {} {} values", what, dims[0], t.name));
      overlay.index = index;
      overlay.intent = intent;
      kept = &overlay.values;
      kept->type = t.type;
      kept->rows = static_cast<uint64_t>(dims[0]);
      kept->swapped =
          encoding != Encoding::ascii && *big_endian != (std::endian::native == std::endian::big);
    }
  }

  // <Label Key="" Red="" Green="" Blue="" Alpha="">name</Label>: colours in [0, 1]; Index="" in
  // older files.
  void start_label(const char** attrs) {
    GiftiLabel l;
    std::optional<int64_t> key, index;
    for (const char** p = attrs; p[0] && p[1]; p += 2) {
      const std::string_view name = p[0], value = p[1];
      const int channel = name == "Red"     ? 0
                          : name == "Green" ? 1
                          : name == "Blue"  ? 2
                          : name == "Alpha" ? 3
                                            : -1;
      if (name == "Key" || name == "Index") {
        int64_t k = 0;
        auto r = std::from_chars(value.data(), value.data() + value.size(), k);
        if (r.ec != std::errc() || r.ptr != value.data() + value.size())
          return fail(fmt::format("label table: {} '{}' is not an integer", name, shown(value)));
        (name == "Key" ? key : index) = k;
      } else if (channel >= 0) {
        std::optional<double> v = parse_header_number<double>(value);
        if (!v || !(*v >= 0.0 && *v <= 1.0))
          return fail(
              fmt::format("label table: {} '{}' is not a number in [0, 1]", name, shown(value)));
        l.rgba[channel] = static_cast<float>(*v);
      }
    }
    // Older GIfTI files number labels by Index; nibabel takes Key where a label has both.
    if (!key && !index) return fail("label table: a <Label> has no Key (or Index)");
    l.key = key ? *key : *index;
    label = std::move(l);
  }

  // At <Data>: the claim must be one that the rest of the file can hold, before anything is
  // decoded or kept.
  void start_data() {
    const auto at = static_cast<uint64_t>(std::max<XML_Index>(0, XML_GetCurrentByteIndex(xml)));
    const uint64_t rest = file_size > at ? file_size - at : 0;
    const std::string what = where();
    if (encoding == Encoding::gzip_base64)
      check_inflatable(bytes, rest * 3 / 4, what);
    else if (encoding == Encoding::base64 ? bytes > rest * 3 / 4 : values > rest / 2 + 1)
      return fail(fmt::format(
          "{}: the dimensions claim {} {} values, more than the rest of the "
          "file ({} bytes) can hold as {}",
          what, values, type.name, rest, encoding == Encoding::base64 ? "base64" : "text"));
    if (kept) kept->bytes.reserve(bytes);
    decoder.emplace(what, encoding, type, values, bytes, kept ? &kept->bytes : nullptr);
  }

  // ASCII text in ColumnMajorOrder. nibabel reads ASCII by its lines, the order unused, and
  // writes a row a line whatever the order says; libgiftiio writes a column a line and reads the
  // values in the stated order. Rows a line are nibabel's rows; any other layout is in column
  // order (a column a line, as libgiftiio writes it; nibabel's arrays there take the wrong
  // shape). Three lines of three could be either: refused.
  void ascii_order() {
    const DataDecoder::Lines& lines = decoder->lines();
    const bool rows_a_line = lines.uniform && lines.width == 3 && lines.count == kept->rows;
    if (rows_a_line && kept->rows == 3)
      return fail(fmt::format(
          "{}: ASCII data in ColumnMajorOrder on 3 lines of 3 values: rows (as nibabel writes "
          "and reads it) or columns (as libgiftiio does)?",
          where()));
    if (rows_a_line) kept->column_major = false;
  }

  // Expat may still call back after a stop: nothing more happens once a fault is known.
  void start(const char* name, const char** attrs) {
    ++depth;
    if (!fault.empty()) return;
    if (depth == 1 && std::strcmp(name, "GIFTI") != 0)
      return fail(fmt::format("the root element is <{}>, not <GIFTI>", shown(name)));
    if (depth == 1)
      for (const char** p = attrs; p[0] && p[1]; p += 2)
        if (std::strcmp(p[0], "NumberOfDataArrays") == 0) claimed_arrays = p[1];
    if (depth > 1) {
      auto rule = parents().find(std::string_view(name));
      if (rule == parents().end())
        return fail(fmt::format("<{}> is not a GIfTI element", shown(name)));
      if (!parent_allowed(rule->second, stack.back()))
        return fail(
            fmt::format("<{}> inside <{}> (it belongs in <{}>)", shown(name), shown(stack.back()),
                        rule->second == "GIFTI|DataArray" ? "GIFTI> or <DataArray" : rule->second));
    }
    stack.emplace_back(name);
    if (std::strcmp(name, "Label") == 0) start_label(attrs);
    // The vertices' coordinate systems (nibabel's GiftiCoordSystem), read by gifti_reader.
    if (std::strcmp(name, "CoordinateSystemTransformMatrix") == 0 && checked >= 0 &&
        checked == pointset && surface.coordinate_systems.size() < 16)
      surface.coordinate_systems.emplace_back();
    if (depth == 2 && std::strcmp(name, "DataArray") == 0) {
      checked = -1;
      decoder.reset();
      start_array(attrs);
    } else if (depth == 3 && checked >= 0 && std::strcmp(name, "Data") == 0) {
      if (has_data) return fail(fmt::format("{} has two <Data> elements", where()));
      has_data = true;
      data_depth = depth;
      start_data();
    }
  }

  void end() {
    if (!fault.empty()) return;
    if (stack.back() == "Label" && label) {
      if (label->name.size() > 4096) return fail("label table: a label's name is over 4096 bytes");
      overlay.labels.push_back(std::move(*label));
      label.reset();
      if (overlay.labels.size() > (1u << 20)) return fail("label table: over 2^20 labels");
    }
    stack.pop_back();
    if (data_depth != 0 && depth == data_depth) {
      data_depth = 0;
      if (std::string why = decoder->finish(); !why.empty())
        return fail(fmt::format("{}: {}", where(), why));
      if (kept && kept->column_major && encoding == Encoding::ascii) ascii_order();
    }
    if (depth == 2 && checked >= 0) {
      if (!has_data) return fail(fmt::format("{} has no <Data>", where()));
      checked = -1;
      decoder.reset();
    }
    --depth;
  }

  void text(std::string_view s) {
    if (fault.empty() && label && !stack.empty() && stack.back() == "Label") {
      if (label->name.size() <= 4096) label->name += s;
      return;
    }
    if (fault.empty() && stack.size() >= 2 &&
        stack[stack.size() - 2] == "CoordinateSystemTransformMatrix" && checked >= 0 &&
        checked == pointset && !surface.coordinate_systems.empty()) {
      GiftiCoordinateSystem& c = surface.coordinate_systems.back();
      std::string* field = stack.back() == "DataSpace"          ? &c.data_space
                           : stack.back() == "TransformedSpace" ? &c.transformed_space
                                                                : &c.matrix;
      if (field->size() + s.size() > 4096)
        return fail(fmt::format("{}: <{}> is over 4096 bytes", where(), stack.back()));
      *field += s;
      return;
    }
    if (!fault.empty() || data_depth == 0 || depth != data_depth || !decoder) return;
    if (std::string why = decoder->add(s); !why.empty()) fail(fmt::format("{}: {}", where(), why));
  }
};

// A count that is not the number of arrays is a damaged file (libgiftiio warned and read on).
bool claimed_arrays_ok(const std::string& claimed, int arrays) {
  int n = -1;
  auto r = std::from_chars(claimed.data(), claimed.data() + claimed.size(), n);
  return r.ec == std::errc() && r.ptr == claimed.data() + claimed.size() && n == arrays;
}

}  // namespace

namespace {

void parse_gifti(Parser& p, const std::filesystem::path& file) {
  p.file = file;
  auto fail = [&](const std::string& why) {
    throw Error(fmt::format("{}: {}", file.string(), why));
  };
  const XmlParser xml = make_xml_parser();
  if (!xml) fail("cannot start the XML parser");
  p.xml = xml.get();
  XML_SetUserData(p.xml, &p);
  // No exception may cross expat's C frames: the handlers turn them into a stop.
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
      [](void* u, const char*) {
        auto* self = static_cast<Parser*>(u);
        try {
          self->end();
        } catch (const std::exception& e) {
          self->fail(e.what());
        }
      });
  XML_SetCharacterDataHandler(p.xml, [](void* u, const char* s, int len) {
    auto* self = static_cast<Parser*>(u);
    try {
      self->text({s, static_cast<size_t>(len)});
    } catch (const std::exception& e) {
      self->fail(e.what());
    }
  });
  // GIfTI readers take CDATA sections only as the text of names, labels and matrices.
  XML_SetStartCdataSectionHandler(p.xml, [](void* u) {
    auto* self = static_cast<Parser*>(u);
    if (!self->stack.empty() && self->stack.back() == "Data")
      self->fail("a <Data> element holds a CDATA section");
  });
  // Entities are never needed by GIfTI and are how XML bombs grow.
  XML_SetEntityDeclHandler(
      p.xml, [](void* u, const char*, int, const char*, int, const char*, const char*, const char*,
                const char*) { static_cast<Parser*>(u)->fail("the file declares XML entities"); });

  std::ifstream in = open_input_stream(file);
  in.seekg(0, std::ios::end);
  p.file_size = static_cast<uint64_t>(std::max<std::streamoff>(0, in.tellg()));
  in.seekg(0);
  std::vector<char> buffer(1 << 16);
  bool done = false;
  while (!done) {
    in.read(buffer.data(), static_cast<std::streamsize>(buffer.size()));
    const auto n = static_cast<int>(in.gcount());
    done = n < static_cast<int>(buffer.size());
    if (XML_Parse(p.xml, buffer.data(), n, done ? XML_TRUE : XML_FALSE) == XML_STATUS_ERROR) {
      if (!p.fault.empty()) fail(p.fault);
      fail(fmt::format("not a GIfTI file: {} at line {}", XML_ErrorString(XML_GetErrorCode(p.xml)),
                       XML_GetCurrentLineNumber(p.xml)));
    }
  }
  if (!p.fault.empty()) fail(p.fault);
  if (claimed_arrays_ok(p.claimed_arrays, p.arrays) == false)
    fail(fmt::format("NumberOfDataArrays is '{}', but the file holds {} data arrays",
                     shown(p.claimed_arrays), p.arrays));
}

}  // namespace

GiftiSurface read_gifti_arrays(const std::filesystem::path& file) {
  Parser p;
  parse_gifti(p, file);
  auto fail = [&](const std::string& why) {
    throw Error(fmt::format("{}: {}", file.string(), why));
  };
  if (p.pointset < 0 && !p.value_intents.empty())
    fail(fmt::format(
        "no NIFTI_INTENT_POINTSET data array (the vertices): its data arrays ({}) are values "
        "for the vertices of a surface, an overlay to open with the surface it belongs to",
        fmt::join(p.value_intents, ", ")));
  if (p.pointset < 0) fail("no NIFTI_INTENT_POINTSET data array (the vertices)");
  if (p.triangle < 0) fail("no NIFTI_INTENT_TRIANGLE data array (the triangles)");
  return std::move(p.surface);
}

GiftiOverlay read_gifti_overlay(const std::filesystem::path& file, int array) {
  Parser p;
  p.overlay_mode = true;
  p.wanted = array;
  parse_gifti(p, file);
  auto fail = [&](const std::string& why) {
    throw Error(fmt::format("{}: {}", file.string(), why));
  };
  if (p.sparse)
    fail(
        "holds NIFTI_INTENT_NODE_INDEX (sparse data on some vertices), which intermix does not "
        "read");
  if (array >= p.arrays)
    fail(fmt::format("has {} data arrays: there is no array {}", p.arrays, array));
  if (p.overlay.index < 0)
    fail("holds no data array of per-vertex values (all are POINTSET, TRIANGLE or VECTOR)");
  return std::move(p.overlay);
}

}  // namespace imx::detail
