#include "io/mesh/gltf_check.hpp"

#include <cstdint>
#include <cstring>
#include <fstream>
#include <string>
#include <vector>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "intermix/error.hpp"
#include "intermix/limits.hpp"
#include "io/streams/input_file.hpp"

namespace imx::detail {
namespace {

constexpr int kMaxJsonDepth = 256;
constexpr size_t kMaxNodeDepth = 1024;

struct GltfFile {
  std::string json;
  uint64_t bin_size = 0;  // the GLB's BIN chunk, 0 without one
};

uint32_t le32(const std::string& bytes, size_t at) {
  uint32_t v;
  std::memcpy(&v, bytes.data() + at, 4);
  return v;
}

GltfFile read_gltf(const std::filesystem::path& file, const std::string& what) {
  const InputFd fd = open_input(file, what);
  const uint64_t size = fd.size();
  check_memory(size, what);
  std::ifstream in(path_of_open(fd, file), std::ios::binary);
  std::string bytes(static_cast<size_t>(size), '\0');
  in.read(bytes.data(), static_cast<std::streamsize>(size));
  if (static_cast<uintmax_t>(in.gcount()) != size)
    throw Error(fmt::format("{}: cannot read", what));
  if (bytes.size() < 4 || bytes.compare(0, 4, "glTF") != 0) return {bytes, 0};

  // GLB: a 12-byte header, then chunks of (length, type, data); the first is the JSON.
  if (bytes.size() < 20) throw Error(fmt::format("{}: GLB file shorter than its header", what));
  if (le32(bytes, 4) != 2)
    throw Error(fmt::format("{}: GLB version {} (only glTF 2 is read)", what, le32(bytes, 4)));
  if (le32(bytes, 8) > bytes.size())
    throw Error(fmt::format("{}: the GLB header gives a length of {} bytes, but the file has {}",
                            what, le32(bytes, 8), bytes.size()));
  GltfFile out;
  size_t at = 12;
  for (int chunk = 0; at + 8 <= bytes.size(); ++chunk) {
    const uint64_t length = le32(bytes, at), type = le32(bytes, at + 4);
    if (length > bytes.size() - at - 8)
      throw Error(fmt::format("{}: GLB chunk {} claims {} bytes, but {} remain in the file", what,
                              chunk, length, bytes.size() - at - 8));
    if (chunk == 0 && type != 0x4E4F534A)
      throw Error(fmt::format("{}: the first GLB chunk is not JSON", what));
    if (chunk == 0) out.json = bytes.substr(at + 8, static_cast<size_t>(length));
    if (chunk == 1 && type == 0x004E4942) out.bin_size = length;
    at += 8 + static_cast<size_t>(length);
  }
  if (out.json.empty()) throw Error(fmt::format("{}: the GLB has no JSON chunk", what));
  return out;
}

// A SAX pass that only counts nesting, before the document is built (nlohmann's own depth
// callback is quadratic in an array's length).
struct DepthCheck : nlohmann::json_sax<nlohmann::json> {
  int depth = 0;
  bool too_deep = false;
  bool open() { return !(too_deep = ++depth > kMaxJsonDepth); }
  bool close() { return --depth, true; }
  bool null() override { return true; }
  bool boolean(bool) override { return true; }
  bool number_integer(number_integer_t) override { return true; }
  bool number_unsigned(number_unsigned_t) override { return true; }
  bool number_float(number_float_t, const string_t&) override { return true; }
  bool string(string_t&) override { return true; }
  bool binary(binary_t&) override { return true; }
  bool start_object(std::size_t) override { return open(); }
  bool key(string_t&) override { return true; }
  bool end_object() override { return close(); }
  bool start_array(std::size_t) override { return open(); }
  bool end_array() override { return close(); }
  bool parse_error(std::size_t, const std::string&, const nlohmann::detail::exception&) override {
    return false;
  }
};

nlohmann::json parse_json(const std::string& text, const std::string& what) {
  DepthCheck depth;
  nlohmann::json::sax_parse(text, &depth);
  if (depth.too_deep)
    throw Error(fmt::format("{}: JSON nested deeper than {} levels", what, kMaxJsonDepth));
  try {
    return nlohmann::json::parse(text);
  } catch (const nlohmann::json::exception& e) {
    throw Error(fmt::format("{}: not valid glTF JSON: {}", what, e.what()));
  }
}

// A non-negative integer field, `fallback` when absent.
uint64_t count_of(const nlohmann::json& object, const char* key, const std::string& where,
                  uint64_t fallback = 0) {
  if (!object.is_object() || !object.contains(key)) return fallback;
  const nlohmann::json& v = object[key];
  if (!v.is_number_unsigned())
    throw Error(
        fmt::format("{}.{}: expected a non-negative integer, got {}", where, key, v.dump()));
  return v.get<uint64_t>();
}

const nlohmann::json& array_of(const nlohmann::json& doc, const char* key) {
  static const nlohmann::json empty = nlohmann::json::array();
  return doc.is_object() && doc.contains(key) && doc[key].is_array() ? doc[key] : empty;
}

// Children in range, each node with at most one parent, and no path deeper than kMaxNodeDepth.
void check_nodes(const nlohmann::json& doc, const std::string& what) {
  const nlohmann::json& nodes = array_of(doc, "nodes");
  std::vector<int> parents(nodes.size(), 0);
  for (size_t i = 0; i < nodes.size(); ++i) {
    const nlohmann::json& n = nodes[i];
    if (!n.is_object() || !n.contains("children")) continue;
    if (!n["children"].is_array())
      throw Error(fmt::format("{}: nodes[{}].children is not an array", what, i));
    for (const nlohmann::json& c : n["children"]) {
      if (!c.is_number_unsigned() || c.get<uint64_t>() >= nodes.size())
        throw Error(fmt::format("{}: nodes[{}].children names node {}, but there are {} nodes",
                                what, i, c.dump(), nodes.size()));
      if (++parents[c.get<size_t>()] > 1 || c.get<size_t>() == i)
        throw Error(
            fmt::format("{}: node {} has more than one parent (a node tree may not share "
                        "or loop)",
                        what, c.get<size_t>()));
    }
  }
  // Walk down from the roots with an explicit stack; a node never reached lies on a cycle.
  std::vector<std::pair<size_t, size_t>> stack;  // (node, depth)
  size_t reached = 0;
  for (size_t i = 0; i < nodes.size(); ++i)
    if (parents[i] == 0) stack.emplace_back(i, 1);
  while (!stack.empty()) {
    auto [node, depth] = stack.back();
    stack.pop_back();
    ++reached;
    if (depth > kMaxNodeDepth)
      throw Error(fmt::format("{}: the node tree is deeper than {} levels", what, kMaxNodeDepth));
    if (nodes[node].is_object() && nodes[node].contains("children"))
      for (const nlohmann::json& c : nodes[node]["children"])
        stack.emplace_back(c.get<size_t>(), depth + 1);
  }
  if (reached != nodes.size()) throw Error(fmt::format("{}: the node tree has a cycle", what));
}

uint64_t component_bytes(uint64_t type) {
  return type == 5126 || type == 5125 ? 4 : type == 5122 || type == 5123 ? 2 : 1;
}

uint64_t components(const std::string& type) {
  if (type == "VEC2") return 2;
  if (type == "VEC3") return 3;
  if (type == "VEC4" || type == "MAT2") return 4;
  if (type == "MAT3") return 9;
  if (type == "MAT4") return 16;
  return 1;
}

// Buffers no larger than their data and the budget; views inside their buffers; accessors
// inside their views (or, without one, within the budget: assimp fills them with zeros).
void check_sizes(const nlohmann::json& doc, const GltfFile& gltf, const std::string& what) {
  const nlohmann::json& buffers = array_of(doc, "buffers");
  std::vector<uint64_t> buffer_sizes;
  uint64_t total = 0;
  for (size_t i = 0; i < buffers.size(); ++i) {
    const std::string where = fmt::format("buffers[{}]", i);
    const uint64_t length = count_of(buffers[i], "byteLength", where);
    const bool embedded = !buffers[i].is_object() || !buffers[i].contains("uri");
    if (embedded && length > gltf.bin_size)
      throw Error(fmt::format("{}: {}.byteLength is {}, but the GLB's binary chunk holds {}", what,
                              where, length, gltf.bin_size));
    if (!embedded && buffers[i]["uri"].is_string()) {
      const std::string& uri = buffers[i]["uri"].get_ref<const std::string&>();
      if (uri.rfind("data:", 0) == 0 && length > uri.size())
        throw Error(
            fmt::format("{}: {}.byteLength is {}, more than its {}-character data URI "
                        "holds",
                        what, where, length, uri.size()));
    }
    buffer_sizes.push_back(length);
    total += length;
  }
  check_memory(total, fmt::format("{}: its buffers", what));

  const nlohmann::json& views = array_of(doc, "bufferViews");
  std::vector<uint64_t> view_sizes;
  for (size_t i = 0; i < views.size(); ++i) {
    const std::string where = fmt::format("bufferViews[{}]", i);
    const uint64_t buffer = count_of(views[i], "buffer", where);
    const uint64_t offset = count_of(views[i], "byteOffset", where);
    const uint64_t length = count_of(views[i], "byteLength", where);
    if (buffer >= buffer_sizes.size() || offset > buffer_sizes[buffer] ||
        length > buffer_sizes[buffer] - offset)
      throw Error(fmt::format("{}: {} (offset {}, {} bytes) lies outside its buffer", what, where,
                              offset, length));
    view_sizes.push_back(length);
  }

  const nlohmann::json& accessors = array_of(doc, "accessors");
  for (size_t i = 0; i < accessors.size(); ++i) {
    const nlohmann::json& a = accessors[i];
    const std::string where = fmt::format("accessors[{}]", i);
    const uint64_t count = count_of(a, "count", where);
    const std::string type = a.is_object() && a.contains("type") && a["type"].is_string()
                                 ? a["type"].get<std::string>()
                                 : "SCALAR";
    const uint64_t element =
        components(type) * component_bytes(count_of(a, "componentType", where));
    if (count > (uint64_t{1} << 40) / element)
      throw Error(fmt::format("{}: {}.count {} is far too large", what, where, count));
    const uint64_t bytes = count * element;
    if (a.is_object() && a.contains("bufferView")) {
      const uint64_t view = count_of(a, "bufferView", where);
      const uint64_t offset = count_of(a, "byteOffset", where);
      if (view >= view_sizes.size() || offset > view_sizes[view] ||
          bytes > view_sizes[view] - offset)
        throw Error(fmt::format("{}: {} ({} elements of {} bytes) does not fit in its buffer view",
                                what, where, count, element));
    } else {
      check_memory(bytes, fmt::format("{}: {}", what, where));
    }
  }
}

}  // namespace

void check_gltf(const std::filesystem::path& file) {
  const std::string what = file.string();
  const GltfFile gltf = read_gltf(file, what);
  const nlohmann::json doc = parse_json(gltf.json, what);
  check_nodes(doc, what);
  check_sizes(doc, gltf, what);
}

}  // namespace imx::detail
