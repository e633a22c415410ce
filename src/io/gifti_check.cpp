#include "io/gifti_check.hpp"

#include <expat.h>
#include <zlib.h>

#include <array>
#include <charconv>
#include <cstring>
#include <fstream>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <type_traits>
#include <vector>

#include <fmt/format.h>

#include "intermix/error.hpp"
#include "intermix/limits.hpp"
#include "io/header_text.hpp"

namespace imx::detail {
namespace {

// libgiftiio sizes its buffers in int arithmetic (with 1% slack for zlib): stay well below.
constexpr uint64_t kMaxArrayBytes = uint64_t{1} << 30;
constexpr size_t kMaxToken = 64;  // one ASCII number

enum class Encoding { ascii, base64, gzip_base64 };
enum class Kind { floating, integer };

struct TypeInfo {
  const char* name;
  int bytes;
  Kind kind;
};

// The data types intermix reads, by their GIfTI names.
const std::map<std::string, TypeInfo, std::less<>>& types() {
  static const std::map<std::string, TypeInfo, std::less<>> table = {
      {"NIFTI_TYPE_FLOAT32", {"float32", 4, Kind::floating}},
      {"NIFTI_TYPE_FLOAT64", {"float64", 8, Kind::floating}},
      {"NIFTI_TYPE_INT8", {"int8", 1, Kind::integer}},
      {"NIFTI_TYPE_UINT8", {"uint8", 1, Kind::integer}},
      {"NIFTI_TYPE_INT16", {"int16", 2, Kind::integer}},
      {"NIFTI_TYPE_UINT16", {"uint16", 2, Kind::integer}},
      {"NIFTI_TYPE_INT32", {"int32", 4, Kind::integer}},
      {"NIFTI_TYPE_UINT32", {"uint32", 4, Kind::integer}},
      {"NIFTI_TYPE_INT64", {"int64", 8, Kind::integer}},
      {"NIFTI_TYPE_UINT64", {"uint64", 8, Kind::integer}},
  };
  return table;
}

int base64_value(unsigned char c) {
  if (c >= 'A' && c <= 'Z') return c - 'A';
  if (c >= 'a' && c <= 'z') return c - 'a' + 26;
  if (c >= '0' && c <= '9') return c - '0' + 52;
  if (c == '+') return 62;
  if (c == '/') return 63;
  return -1;
}

// Counts what the <Data> text of one checked array decodes to, chunk by chunk.
class DataCounter {
 public:
  DataCounter(Encoding encoding, Kind kind, uint64_t values, uint64_t bytes)
      : encoding_(encoding), kind_(kind), values_(values), bytes_(bytes) {
    if (encoding_ == Encoding::gzip_base64) {
      stream_ = z_stream{};
      if (inflateInit(&stream_) != Z_OK) throw Error("zlib cannot start inflating");
      inflating_ = true;
    }
  }
  ~DataCounter() {
    if (inflating_) inflateEnd(&stream_);
  }
  DataCounter(const DataCounter&) = delete;
  DataCounter& operator=(const DataCounter&) = delete;

  // An empty string, or why the text is not the claimed data.
  std::string add(std::string_view text) {
    if (!fault_.empty()) return fault_;
    if (encoding_ == Encoding::ascii) {
      for (char c : text) {
        if (std::isspace(static_cast<unsigned char>(c))) {
          end_token();
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

 private:
  void end_token() {
    if (token_.empty()) return;
    const char* b = token_.data();
    const char* e = b + token_.size();
    if (*b == '+') ++b;
    bool ok;
    if (kind_ == Kind::floating) {
      double v;
      auto r = std::from_chars(b, e, v);
      ok = r.ec == std::errc() && r.ptr == e;
    } else {
      long long v;
      auto r = std::from_chars(b, e, v);
      ok = r.ec == std::errc() && r.ptr == e;
    }
    ++count_;
    if (!ok)
      fault_ = fmt::format("value {} '{}' is not {}", count_, shown(token_),
                           kind_ == Kind::floating ? "a number" : "an integer");
    else if (count_ > values_)
      fault_ = fmt::format("the data holds more values than the {} the dimensions claim", values_);
    token_.clear();
  }

  void emit(const uint8_t* data, int n) {
    decoded_ += static_cast<uint64_t>(n);
    if (encoding_ == Encoding::base64) {
      if (decoded_ > bytes_) fault_ = fmt::format("the data holds more than {} bytes", bytes_);
      return;
    }
    if (ended_) return;  // bytes after the stream: libgiftiio ignores them too
    stream_.next_in = const_cast<Bytef*>(data);
    stream_.avail_in = static_cast<uInt>(n);
    while (stream_.avail_in > 0 && !ended_) {
      stream_.next_out = scratch_.data();
      stream_.avail_out = static_cast<uInt>(scratch_.size());
      const int rc = inflate(&stream_, Z_NO_FLUSH);
      inflated_ += scratch_.size() - stream_.avail_out;
      if (inflated_ > bytes_) {
        fault_ =
            fmt::format("the data inflates to more than the {} bytes the dimensions claim", bytes_);
        return;
      }
      if (rc == Z_STREAM_END)
        ended_ = true;
      else if (rc != Z_OK && rc != Z_BUF_ERROR) {
        fault_ = "the compressed data is corrupt";
        return;
      }
    }
  }

  Encoding encoding_;
  Kind kind_;
  uint64_t values_, bytes_;
  std::string fault_;
  // ASCII
  std::string token_;
  uint64_t count_ = 0;
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

// The parent each GIfTI element must have (GIFTI itself is the root). libgiftiio trusts the
// nesting: a <Name> under the wrong parent makes it write before its arrays.
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
  XML_Parser xml = nullptr;
  std::string fault;
  int depth = 0;
  std::vector<std::string> stack;  // open elements
  int arrays = 0;                  // DataArray elements seen
  std::string claimed_arrays;      // the GIFTI element's NumberOfDataArrays
  int checked = -1;                // the array being checked, or -1
  int data_depth = 0;              // depth of the checked array's <Data>, or 0
  bool has_data = false;           // the checked array had a <Data> element
  uint64_t total_bytes = 0;
  std::optional<DataCounter> counter;
  GiftiSurfaceArrays found;

  void fail(std::string message) {
    if (fault.empty()) fault = std::move(message);
    XML_StopParser(xml, XML_FALSE);
  }

  std::string where() const { return fmt::format("data array {}", checked); }

  // Every array, since libgiftiio allocates and decodes them all; the surface's two also need
  // the shape and types of vertices and triangles.
  void start_array(const char** attrs) {
    const int index = arrays++;
    std::map<std::string, std::string, std::less<>> a;
    for (const char** p = attrs; p[0] && p[1]; p += 2) a[p[0]] = p[1];
    auto get = [&](std::string_view key) {
      auto it = a.find(key);
      return it == a.end() ? std::string() : it->second;
    };
    const std::string intent = get("Intent");
    const bool pointset = intent == "NIFTI_INTENT_POINTSET" && found.pointset < 0;
    const bool triangle = intent == "NIFTI_INTENT_TRIANGLE" && found.triangle < 0;
    checked = index;
    has_data = false;
    if (pointset) found.pointset = index;
    if (triangle) found.triangle = index;
    const std::string what = fmt::format("data array {} ({})", index, shown(intent));

    const std::string external = get("ExternalFileName");
    if (!external.empty())
      return fail(fmt::format("{}: external data files (ExternalFileName '{}') are not read", what,
                              shown(external)));
    const std::string encoding_name = get("Encoding");
    Encoding encoding;
    if (encoding_name == "ASCII")
      encoding = Encoding::ascii;
    else if (encoding_name == "Base64Binary")
      encoding = Encoding::base64;
    else if (encoding_name == "GZipBase64Binary")
      encoding = Encoding::gzip_base64;
    else
      return fail(fmt::format("{}: Encoding '{}' is not ASCII, Base64Binary or GZipBase64Binary",
                              what, shown(encoding_name)));
    const std::string endian = get("Endian");
    if (encoding != Encoding::ascii && endian != "LittleEndian" && endian != "BigEndian")
      return fail(
          fmt::format("{}: Endian '{}' is not LittleEndian or BigEndian", what, shown(endian)));
    const std::string order = get("ArrayIndexingOrder");
    if (order != "RowMajorOrder" && order != "ColumnMajorOrder")
      return fail(
          fmt::format("{}: ArrayIndexingOrder '{}' is not RowMajorOrder or ColumnMajorOrder", what,
                      shown(order)));
    const std::string type_name = get("DataType");
    auto type = types().find(type_name);
    if (type == types().end())
      return fail(
          fmt::format("{}: DataType '{}' is not a type intermix reads", what, shown(type_name)));
    const TypeInfo& t = type->second;
    // libgiftiio's ASCII decoder has no unsigned 32- or 64-bit case.
    if (encoding == Encoding::ascii &&
        (type_name == "NIFTI_TYPE_UINT32" || type_name == "NIFTI_TYPE_UINT64"))
      return fail(fmt::format("{}: ASCII data of type {} is not read", what, t.name));

    const std::string dimensionality = get("Dimensionality");
    int n_dims = 0;
    auto r = std::from_chars(dimensionality.data(), dimensionality.data() + dimensionality.size(),
                             n_dims);
    if (r.ec != std::errc() || r.ptr != dimensionality.data() + dimensionality.size() ||
        n_dims < 1 || n_dims > 6)
      return fail(
          fmt::format("{}: Dimensionality '{}' is not 1 to 6", what, shown(dimensionality)));
    int dims[6] = {0, 0, 0, 0, 0, 0};
    uint64_t values = 1;
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
    const uint64_t bytes = values * static_cast<uint64_t>(t.bytes);
    if (bytes > kMaxArrayBytes)
      return fail(fmt::format("{}: {} {} values ({}) are more than intermix reads ({})", what,
                              values, t.name, format_bytes(bytes), format_bytes(kMaxArrayBytes)));

    if (pointset || triangle) {
      if (pointset && t.kind != Kind::floating)
        return fail(fmt::format("{}: DataType {} is not float32 or float64", what, t.name));
      if (triangle && t.kind != Kind::integer)
        return fail(fmt::format("{}: DataType {} is not an integer type", what, t.name));
      if (n_dims != 2)
        return fail(fmt::format("{}: Dimensionality {} is not 2 (one row of 3 per {})", what,
                                n_dims, pointset ? "vertex" : "triangle"));
      if (dims[1] != 3)
        return fail(fmt::format("{}: Dim1 is {}, not 3 ({} per row)", what, dims[1],
                                pointset ? "x, y, z" : "three vertex indices"));
    }
    // libgiftiio holds the data, a compressed copy and its own buffer at once.
    total_bytes += bytes;
    check_memory(3 * total_bytes, what);
    counter.emplace(encoding, t.kind, values, bytes);
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
    if (depth == 2 && std::strcmp(name, "DataArray") == 0) {
      checked = -1;
      counter.reset();
      start_array(attrs);
    } else if (depth == 3 && checked >= 0 && std::strcmp(name, "Data") == 0) {
      if (has_data) return fail(fmt::format("{} has two <Data> elements", where()));
      has_data = true;
      data_depth = depth;
    }
  }

  void end() {
    if (!fault.empty()) return;
    stack.pop_back();
    if (data_depth != 0 && depth == data_depth) {
      data_depth = 0;
      if (std::string why = counter->finish(); !why.empty())
        return fail(fmt::format("{}: {}", where(), why));
    }
    if (depth == 2 && checked >= 0) {
      if (!has_data) return fail(fmt::format("{} has no <Data>", where()));
      checked = -1;
      counter.reset();
    }
    --depth;
  }

  void text(std::string_view s) {
    if (!fault.empty() || data_depth == 0 || depth != data_depth || !counter) return;
    if (std::string why = counter->add(s); !why.empty()) fail(fmt::format("{}: {}", where(), why));
  }
};

// libgiftiio complains on stderr, and reads on, when the count is not the number of arrays.
bool claimed_arrays_ok(const std::string& claimed, int arrays) {
  int n = -1;
  auto r = std::from_chars(claimed.data(), claimed.data() + claimed.size(), n);
  return r.ec == std::errc() && r.ptr == claimed.data() + claimed.size() && n == arrays;
}

}  // namespace

GiftiSurfaceArrays check_gifti(const std::filesystem::path& file) {
  Parser p;
  p.file = file;
  auto fail = [&](const std::string& why) -> GiftiSurfaceArrays {
    throw Error(fmt::format("{}: {}", file.string(), why));
  };
  std::unique_ptr<std::remove_pointer_t<XML_Parser>, decltype(&XML_ParserFree)> xml(
      XML_ParserCreate(nullptr), &XML_ParserFree);
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
  // libgiftiio takes CDATA sections only as the text of names, labels and matrices.
  XML_SetStartCdataSectionHandler(p.xml, [](void* u) {
    auto* self = static_cast<Parser*>(u);
    if (!self->stack.empty() && self->stack.back() == "Data")
      self->fail("a <Data> element holds a CDATA section");
  });
  // Entities are never needed by GIfTI and are how XML bombs grow.
  XML_SetEntityDeclHandler(
      p.xml, [](void* u, const char*, int, const char*, int, const char*, const char*, const char*,
                const char*) { static_cast<Parser*>(u)->fail("the file declares XML entities"); });

  std::ifstream in(file, std::ios::binary);
  if (!in) fail("cannot open the file");
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
  if (p.found.pointset < 0) fail("no NIFTI_INTENT_POINTSET data array (the vertices)");
  if (p.found.triangle < 0) fail("no NIFTI_INTENT_TRIANGLE data array (the triangles)");
  return p.found;
}

}  // namespace imx::detail
