#include "io/mesh/ply_reader.hpp"

#include <algorithm>
#include <atomic>
#include <bit>
#include <cctype>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <iterator>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

#include <fmt/format.h>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <glm/glm.hpp>

#include "core/colour.hpp"
#include "intermix/error.hpp"
#include "io/streams/input_file.hpp"

namespace imx::detail {
namespace {

enum class Format { ascii, binary_le, binary_be };

enum class Type : uint8_t { i8, u8, i16, u16, i32, u32, f32, f64 };

struct Property {
  std::string name;
  Type type = Type::f32;
  bool is_list = false;
  Type count_type = Type::u8;  // lists only
};

struct Element {
  std::string name;
  uint64_t count = 0;
  std::vector<Property> properties;
};

std::optional<Type> parse_type(const std::string& s) {
  if (s == "char" || s == "int8") return Type::i8;
  if (s == "uchar" || s == "uint8") return Type::u8;
  if (s == "short" || s == "int16") return Type::i16;
  if (s == "ushort" || s == "uint16") return Type::u16;
  if (s == "int" || s == "int32") return Type::i32;
  if (s == "uint" || s == "uint32") return Type::u32;
  if (s == "float" || s == "float32") return Type::f32;
  if (s == "double" || s == "float64") return Type::f64;
  return std::nullopt;
}

size_t type_size(Type t) {
  switch (t) {
    case Type::i8:
    case Type::u8:
      return 1;
    case Type::i16:
    case Type::u16:
      return 2;
    case Type::i32:
    case Type::u32:
    case Type::f32:
      return 4;
    case Type::f64:
      return 8;
  }
  return 1;
}

// Reads numbers from the body, as text tokens or as binary values of either byte order.
class BodyReader {
 public:
  BodyReader(const std::string& data, size_t pos, Format format)
      : data_(data), pos_(pos), format_(format) {}

  // False at the end of the data or on a malformed value.
  bool read(Type type, double& out) {
    return format_ == Format::ascii ? read_text(out) : read_binary(type, out);
  }

  size_t pos() const { return pos_; }
  void skip_to(size_t pos) { pos_ = pos; }

 private:
  bool read_text(double& out) {
    while (pos_ < data_.size() && std::isspace(static_cast<unsigned char>(data_[pos_]))) ++pos_;
    if (pos_ < data_.size() && data_[pos_] == '+') ++pos_;  // from_chars takes no plus sign
    if (pos_ == data_.size()) return false;
    const char* begin = data_.data() + pos_;
    const char* end = data_.data() + data_.size();
    auto [ptr, ec] = std::from_chars(begin, end, out);
    if (ec != std::errc() || (ptr != end && !std::isspace(static_cast<unsigned char>(*ptr))))
      return false;
    pos_ += static_cast<size_t>(ptr - begin);
    return true;
  }

  template <class T>
  T load() {
    unsigned char bytes[sizeof(T)];
    std::memcpy(bytes, data_.data() + pos_, sizeof(T));
    bool file_little = format_ == Format::binary_le;
    if (file_little != (std::endian::native == std::endian::little))
      for (size_t i = 0; i < sizeof(T) / 2; ++i) std::swap(bytes[i], bytes[sizeof(T) - 1 - i]);
    T value;
    std::memcpy(&value, bytes, sizeof(T));
    pos_ += sizeof(T);
    return value;
  }

  bool read_binary(Type type, double& out) {
    if (data_.size() - pos_ < type_size(type)) return false;
    switch (type) {
      case Type::i8:
        out = load<int8_t>();
        break;
      case Type::u8:
        out = load<uint8_t>();
        break;
      case Type::i16:
        out = load<int16_t>();
        break;
      case Type::u16:
        out = load<uint16_t>();
        break;
      case Type::i32:
        out = load<int32_t>();
        break;
      case Type::u32:
        out = load<uint32_t>();
        break;
      case Type::f32:
        out = load<float>();
        break;
      case Type::f64:
        out = load<double>();
        break;
    }
    return true;
  }

  const std::string& data_;
  size_t pos_;
  Format format_;
};

// A header line for a message: printable ASCII only, shortened when long.
std::string printable(const std::string& line) {
  std::string out;
  for (char c : line.substr(0, 60)) out += (c >= 32 && c < 127) ? c : '?';
  return line.size() > 60 ? out + "..." : out;
}

class PlyParser {
 public:
  explicit PlyParser(const std::filesystem::path& file) : file_(file) {}

  Mesh parse() {
    std::ifstream in = open_input_stream(file_, {}, std::ios::binary | std::ios::ate);
    data_.resize(static_cast<size_t>(in.tellg()));
    in.seekg(0);
    if (!in.read(data_.data(), static_cast<std::streamsize>(data_.size())))
      fail("cannot read the file");
    size_t body = parse_header();
    BodyReader reader(data_, body, format_);
    Mesh mesh;
    bool has_normals = false, has_colors = false;
    for (const Element& e : elements_)
      if (!read_triangles_in_parallel(reader, e, mesh))
        read_element(reader, e, mesh, has_normals, has_colors);
    for (const glm::uvec3& t : mesh.triangles)
      if (t.x >= mesh.positions.size() || t.y >= mesh.positions.size() ||
          t.z >= mesh.positions.size())
        fail(fmt::format("a face uses vertex {} of {}", std::max({t.x, t.y, t.z}),
                         mesh.positions.size()));
    if (!has_normals) mesh.normals.clear();
    if (!has_colors) mesh.colors.clear();
    return mesh;
  }

 private:
  [[noreturn]] void fail(const std::string& message) const {
    throw Error(fmt::format("{}: {}", file_.string(), message));
  }

  // Parses the header; returns the offset of the first body byte.
  size_t parse_header() {
    size_t pos = 0;
    bool first = true, has_format = false;
    while (true) {
      size_t eol = data_.find('\n', pos);
      if (eol == std::string::npos) fail("the PLY header has no end_header line");
      std::string line = data_.substr(pos, eol - pos);
      if (!line.empty() && line.back() == '\r') line.pop_back();
      pos = eol + 1;
      std::istringstream words(line);
      std::string keyword;
      words >> keyword;
      if (first) {
        if (keyword != "ply") fail("not a PLY file (the first line is not \"ply\")");
        first = false;
        continue;
      }
      if (keyword == "end_header") break;
      if (keyword.empty() || keyword == "comment" || keyword == "obj_info") continue;
      if (keyword == "format") {
        std::string name, version;
        words >> name >> version;
        if (name == "ascii")
          format_ = Format::ascii;
        else if (name == "binary_little_endian")
          format_ = Format::binary_le;
        else if (name == "binary_big_endian")
          format_ = Format::binary_be;
        else
          fail(fmt::format("unknown PLY format '{}'", printable(name)));
        has_format = true;
      } else if (keyword == "element") {
        Element e;
        if (!(words >> e.name >> e.count))
          fail(fmt::format("malformed header line '{}'", printable(line)));
        for (const Element& other : elements_)
          if (other.name == e.name && (e.name == "vertex" || e.name == "face"))
            fail(fmt::format("more than one '{}' element", e.name));
        elements_.push_back(e);
      } else if (keyword == "property") {
        if (elements_.empty()) fail("a property comes before any element");
        Property p;
        std::string type;
        words >> type;
        if (type == "list") {
          std::string count_type, item_type;
          words >> count_type >> item_type >> p.name;
          auto c = parse_type(count_type), t = parse_type(item_type);
          if (!c || !t || p.name.empty())
            fail(fmt::format("malformed header line '{}'", printable(line)));
          p.is_list = true;
          p.count_type = *c;
          p.type = *t;
        } else {
          auto t = parse_type(type);
          words >> p.name;
          if (!t || p.name.empty())
            fail(fmt::format("malformed header line '{}'", printable(line)));
          p.type = *t;
        }
        elements_.back().properties.push_back(p);
      } else {
        fail(fmt::format("unknown PLY header line '{}'", printable(line)));
      }
    }
    if (!has_format) fail("the PLY header has no format line");
    return pos;
  }

  static int find(const Element& e, std::initializer_list<const char*> names) {
    for (size_t i = 0; i < e.properties.size(); ++i)
      for (const char* n : names)
        if (e.properties[i].name == n && !e.properties[i].is_list) return static_cast<int>(i);
    return -1;
  }

  // A colour channel as stored: 8-bit (or 16-bit) integers over their range, floats in [0, 1];
  // either way sRGB-encoded display values, as the 8-bit convention of PLY writers has them.
  static float channel(double value, Type type) {
    double unit = type == Type::f32 || type == Type::f64   ? value
                  : type == Type::u16 || type == Type::i16 ? value / 65535.0
                                                           : value / 255.0;
    return srgb_decode(static_cast<float>(std::isfinite(unit) ? unit : 1.0));
  }

  void read_element(BodyReader& reader, const Element& e, Mesh& mesh, bool& has_normals,
                    bool& has_colors) {
    if (e.properties.empty()) return;  // nothing to read, however large the count
    const bool is_vertex = e.name == "vertex";
    const bool is_face = e.name == "face";
    int x = -1, y = -1, z = -1, nx = -1, ny = -1, nz = -1, indices = -1, r = -1, g = -1, b = -1;
    if (is_vertex) {
      x = find(e, {"x"}), y = find(e, {"y"}), z = find(e, {"z"});
      if (x < 0 || y < 0 || z < 0) fail("the vertex element lacks an x, y or z property");
      nx = find(e, {"nx"}), ny = find(e, {"ny"}), nz = find(e, {"nz"});
      has_normals = nx >= 0 && ny >= 0 && nz >= 0;
      r = find(e, {"red", "diffuse_red"}), g = find(e, {"green", "diffuse_green"});
      b = find(e, {"blue", "diffuse_blue"});
      has_colors = r >= 0 && g >= 0 && b >= 0;  // an alpha channel is read past, not used
      // Each vertex needs at least one byte or character: bound the allocation by the file.
      if (e.count > data_.size()) fail("the vertex count exceeds the file size");
      if (read_vertices_in_parallel(reader, e, mesh, {x, y, z},
                                    has_normals ? glm::ivec3(nx, ny, nz) : glm::ivec3(-1),
                                    has_colors ? glm::ivec3(r, g, b) : glm::ivec3(-1)))
        return;
      mesh.positions.reserve(e.count);
      if (has_colors) mesh.colors.reserve(e.count);
    }
    if (is_face)
      for (size_t i = 0; i < e.properties.size(); ++i)
        if (e.properties[i].is_list &&
            (e.properties[i].name == "vertex_indices" || e.properties[i].name == "vertex_index"))
          indices = static_cast<int>(i);

    std::vector<double> scalars(e.properties.size(), 0.0);
    std::vector<double> list;
    for (uint64_t k = 0; k < e.count; ++k) {
      for (size_t i = 0; i < e.properties.size(); ++i) {
        const Property& p = e.properties[i];
        auto truncated = [&] {
          fail(fmt::format("the data ends or is malformed in element '{}' ({} of {})",
                           printable(e.name), k + 1, e.count));
        };
        if (!p.is_list) {
          if (!reader.read(p.type, scalars[i])) truncated();
          continue;
        }
        double n = 0.0;
        if (!reader.read(p.count_type, n)) truncated();
        if (!(n >= 0.0) || n != std::floor(n) || n > static_cast<double>(data_.size()))
          fail(fmt::format("bad list length {} in element '{}' ({} of {})", n, printable(e.name),
                           k + 1, e.count));
        list.resize(static_cast<size_t>(n));
        for (double& v : list)
          if (!reader.read(p.type, v)) truncated();
        if (static_cast<int>(i) == indices) add_polygon(list, mesh, e, k);
      }
      if (is_vertex) {
        VertexValues v;
        if (!vertex_values(scalars.data(), e, {x, y, z},
                           has_normals ? glm::ivec3(nx, ny, nz) : glm::ivec3(-1),
                           has_colors ? glm::ivec3(r, g, b) : glm::ivec3(-1), v))
          fail(fmt::format("vertex {} has a non-finite coordinate", k));
        mesh.positions.push_back(v.position);
        if (has_normals) mesh.normals.push_back(v.normal);
        if (has_colors) mesh.colors.push_back(v.color);
      }
    }
  }

  struct VertexValues {
    glm::vec3 position, normal, color;
  };

  // One vertex's position, unit normal and linear colour from its property values (normal and
  // colour where their indices are not -1); false for a non-finite position.
  static bool vertex_values(const double* scalars, const Element& e, glm::ivec3 xyz,
                            glm::ivec3 normal, glm::ivec3 rgb, VertexValues& out) {
    glm::dvec3 pos(scalars[xyz.x], scalars[xyz.y], scalars[xyz.z]);
    if (!std::isfinite(pos.x) || !std::isfinite(pos.y) || !std::isfinite(pos.z)) return false;
    out.position = glm::vec3(pos);
    if (normal.x >= 0) {
      glm::dvec3 n(scalars[normal.x], scalars[normal.y], scalars[normal.z]);
      double len = glm::length(n);
      out.normal = glm::vec3(std::isfinite(len) && len > 0.0 ? n / len : glm::dvec3(0.0));
    }
    if (rgb.x >= 0)
      out.color = glm::vec3(channel(scalars[rgb.x], e.properties[rgb.x].type),
                            channel(scalars[rgb.y], e.properties[rgb.y].type),
                            channel(scalars[rgb.z], e.properties[rgb.z].type));
    return true;
  }

  // Binary vertices without lists have one size each: read on every core. False (nothing
  // read) where the element does not qualify or its data ends early, for the one-core path
  // and its messages.
  bool read_vertices_in_parallel(BodyReader& reader, const Element& e, Mesh& mesh, glm::ivec3 xyz,
                                 glm::ivec3 normal, glm::ivec3 rgb) {
    if (format_ == Format::ascii) return false;
    size_t stride = 0;
    for (const Property& p : e.properties) {
      if (p.is_list) return false;
      stride += type_size(p.type);
    }
    const size_t begin = reader.pos();
    if (e.count > (data_.size() - begin) / stride) return false;
    const size_t n = static_cast<size_t>(e.count);
    mesh.positions.resize(n);
    if (normal.x >= 0) mesh.normals.resize(n);
    if (rgb.x >= 0) mesh.colors.resize(n);
    std::atomic<size_t> first_bad{SIZE_MAX};
    tbb::parallel_for(tbb::blocked_range<size_t>(0, n), [&](const auto& range) {
      std::vector<double> scalars(e.properties.size());
      BodyReader at(data_, begin + range.begin() * stride, format_);
      for (size_t k = range.begin(); k != range.end(); ++k) {
        for (size_t i = 0; i < e.properties.size(); ++i) at.read(e.properties[i].type, scalars[i]);
        VertexValues v;
        if (!vertex_values(scalars.data(), e, xyz, normal, rgb, v)) {
          for (size_t seen = first_bad; k < seen && !first_bad.compare_exchange_weak(seen, k);) {
          }
          return;
        }
        mesh.positions[k] = v.position;
        if (normal.x >= 0) mesh.normals[k] = v.normal;
        if (rgb.x >= 0) mesh.colors[k] = v.color;
      }
    });
    if (first_bad != SIZE_MAX)
      fail(fmt::format("vertex {} has a non-finite coordinate", first_bad.load()));
    reader.skip_to(begin + n * stride);
    return true;
  }

  // Binary faces that are all triangles, with no other property, have one size each: read on
  // every core. False (nothing read) otherwise, or on any bad value, for the one-core path.
  bool read_triangles_in_parallel(BodyReader& reader, const Element& e, Mesh& mesh) {
    if (format_ == Format::ascii || e.name != "face" || e.properties.size() != 1) return false;
    const Property& p = e.properties[0];
    if (!p.is_list || (p.name != "vertex_indices" && p.name != "vertex_index")) return false;
    const size_t stride = type_size(p.count_type) + 3 * type_size(p.type);
    const size_t begin = reader.pos();
    if (e.count > (data_.size() - begin) / stride) return false;
    const size_t n = static_cast<size_t>(e.count), before = mesh.triangles.size();
    mesh.triangles.resize(before + n);
    std::atomic<bool> irregular{false};
    tbb::parallel_for(tbb::blocked_range<size_t>(0, n), [&](const auto& range) {
      BodyReader at(data_, begin + range.begin() * stride, format_);
      for (size_t k = range.begin(); k != range.end(); ++k) {
        double count = 0.0, v[3];
        at.read(p.count_type, count);
        for (double& value : v) at.read(p.type, value);
        for (double value : v)
          if (!(value >= 0.0) || value != std::floor(value) || value > 4294967295.0) count = -1.0;
        if (count != 3.0) {
          irregular = true;
          return;
        }
        mesh.triangles[before + k] = {static_cast<uint32_t>(v[0]), static_cast<uint32_t>(v[1]),
                                      static_cast<uint32_t>(v[2])};
      }
    });
    if (irregular) {
      mesh.triangles.resize(before);
      return false;
    }
    reader.skip_to(begin + n * stride);
    return true;
  }

  // A polygon as a triangle fan; points and lines are dropped.
  void add_polygon(const std::vector<double>& list, Mesh& mesh, const Element& e, uint64_t k) {
    for (double v : list)
      if (!(v >= 0.0) || v != std::floor(v) || v > 4294967295.0)
        fail(fmt::format("face {} of {} has a bad vertex index {}", k, e.count, v));
    for (size_t i = 1; i + 1 < list.size(); ++i)
      mesh.triangles.push_back({static_cast<uint32_t>(list[0]), static_cast<uint32_t>(list[i]),
                                static_cast<uint32_t>(list[i + 1])});
  }

  std::filesystem::path file_;
  std::string data_;
  Format format_ = Format::ascii;
  std::vector<Element> elements_;
};

}  // namespace

Mesh read_ply(const std::filesystem::path& file) {
  return PlyParser(file).parse();
}

}  // namespace imx::detail
