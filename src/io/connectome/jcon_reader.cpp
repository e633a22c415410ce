#include <cmath>
#include <cstdint>
#include <string>
#include <unordered_set>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "intermix/error.hpp"
#include "intermix/limits.hpp"
#include "io/connectome/connectome_matrix.hpp"
#include "io/connectome/jcon.hpp"
#include "io/streams/byte_cursor.hpp"
#include "io/streams/json_depth.hpp"

namespace imx::detail {
namespace {

using Json = nlohmann::json;

constexpr int kMaxJsonDepth = 64;
// nlohmann's document takes at most this many bytes per byte of text ("0," becomes a 16-byte
// value; a short key, a map node of about 80 bytes).
constexpr uint64_t kJsonBytesPerTextByte = 16;

bool nested_too_deep(std::string_view text) {
  return json_nested_deeper_than(text, kMaxJsonDepth);
}

// A value as a message shows it: its JSON, cut short.
std::string shown(const Json& value) {
  if (value.is_array()) return fmt::format("an array of {} values", value.size());
  if (value.is_object()) return "an object";
  if (value.is_string() && value.get_ref<const std::string&>().size() > 40)
    return Json(value.get_ref<const std::string&>().substr(0, 37))
               .dump(-1, ' ', false, Json::error_handler_t::replace) +
           "...";
  return value.dump();
}

// A field's name, made only for a message: "nodes.X[3]", "edges[5].first".
struct Field {
  std::string_view base;
  size_t index = SIZE_MAX;  // SIZE_MAX: no index
  std::string_view key{};
  size_t matrix_n = 0;  // an index into an n x n matrix, also shown as row and column

  std::string str() const {
    std::string s(base);
    if (index != SIZE_MAX) s += fmt::format("[{}]", index);
    if (matrix_n)
      s += fmt::format(" (row {}, column {}, from 0)", index / matrix_n, index % matrix_n);
    if (!key.empty()) s += fmt::format(".{}", key);
    return s;
  }
};

class JconReader {
 public:
  JconReader(const std::filesystem::path& file, std::vector<std::string>& notes)
      : what_(file.string()), notes_(notes) {}

  Connectome read(const std::filesystem::path& file) {
    const Json doc = parse(read_file_bytes(file));
    if (!doc.is_object()) fail("the top level", "is not a JSON object");
    if (const auto type = doc.find("data_type"); type != doc.end() && *type == "fs_pointset")
      return read_point_set(doc);
    const auto nodes = doc.find("nodes");
    if (nodes == doc.end()) fail("nodes", "is missing: not a connectome");
    const auto edges = doc.find("edges");
    const Json* edge_field = edges == doc.end() || edges->is_null() ? nullptr : &*edges;

    Connectome out;
    out.style = read_style(doc);
    if (nodes->is_object()) {
      read_dense_nodes(*nodes, out.nodes);
      if (edge_field) out.edges = read_dense_edges(*edge_field, out.nodes.size());
    } else if (nodes->is_array()) {
      read_sparse_nodes(*nodes, out.nodes);
      if (edge_field) out.edges = read_sparse_edges(*edge_field, out.nodes.size());
    } else {
      fail("nodes",
           "is neither an object of arrays (names, X, Y, Z, Color, Size) nor an array "
           "of node objects");
    }
    if (!edge_field) notes_.push_back(fmt::format("{}: no edges (the file has nodes only)", what_));
    return out;
  }

 private:
  [[noreturn]] void fail(std::string_view field, std::string_view message) const {
    throw Error(fmt::format("{}: {} {}", what_, field, message));
  }

  Json parse(const std::string& text) const {
    check_memory(kJsonBytesPerTextByte * text.size(), what_ + " (its JSON document)");
    if (nested_too_deep(text))
      throw Error(fmt::format("{}: JSON nested deeper than {} levels", what_, kMaxJsonDepth));
    try {
      return Json::parse(text);
    } catch (const Json::exception& e) {
      throw Error(fmt::format("{}: not valid JSON: {}", what_, e.what()));
    }
  }

  // A finite number that fits a float.
  float number(const Json& value, const Field& field) const {
    if (!value.is_number()) fail(field.str(), fmt::format("is {}, not a number", shown(value)));
    const float f = static_cast<float>(value.get<double>());
    if (!std::isfinite(f))
      fail(field.str(), fmt::format("is {}, not a finite number", shown(value)));
    return f;
  }

  std::string text(const Json& value, const Field& field) const {
    if (value.is_string()) return value.get<std::string>();
    if (value.is_number()) return value.dump();  // NiiVue shows a number as its digits
    fail(field.str(), fmt::format("is {}, not a string", shown(value)));
  }

  // A node index of `n`: an integer (or a number of integral value, as JavaScript indexes) < n.
  uint32_t node_index(const Json& value, size_t n, const Field& field) const {
    if (value.is_number()) {
      const double d = value.get<double>();
      if (d >= 0 && d < static_cast<double>(n) && d == std::floor(d))
        return static_cast<uint32_t>(d);
    }
    fail(field.str(), fmt::format("is {}, not the index of one of the {} nodes", shown(value), n));
  }

  ConnectomeStyle read_style(const Json& doc) const {
    ConnectomeStyle style;
    const auto get_text = [&](const char* key, std::optional<std::string>& to) {
      if (const auto it = doc.find(key); it != doc.end() && !it->is_null()) {
        if (!it->is_string()) fail(key, fmt::format("is {}, not a string", shown(*it)));
        to = it->get<std::string>();
      }
    };
    const auto get_number = [&](const char* key, std::optional<float>& to) {
      if (const auto it = doc.find(key); it != doc.end() && !it->is_null()) to = number(*it, {key});
    };
    get_text("name", style.name);
    get_text("nodeColormap", style.node_colormap);
    get_text("nodeColormapNegative", style.node_colormap_negative);
    get_number("nodeMinColor", style.node_min_color);
    get_number("nodeMaxColor", style.node_max_color);
    get_number("nodeScale", style.node_scale);
    get_text("edgeColormap", style.edge_colormap);
    get_text("edgeColormapNegative", style.edge_colormap_negative);
    get_number("edgeMin", style.edge_min);
    get_number("edgeMax", style.edge_max);
    get_number("edgeScale", style.edge_scale);
    return style;
  }

  // nodes.<key>: an array of `n` entries (n: the names' count, as NiiVue counts), or nullptr
  // when absent and optional.
  const Json* dense_array(const Json& nodes, const char* key, size_t n, bool required) const {
    const std::string field = fmt::format("nodes.{}", key);
    const auto it = nodes.find(key);
    if (it == nodes.end() || it->is_null()) {
      if (required) fail(field, "is missing (the dense layout needs names, X, Y and Z)");
      return nullptr;
    }
    if (!it->is_array()) fail(field, fmt::format("is {}, not an array", shown(*it)));
    if (it->size() != n)
      fail(field, fmt::format("has {} values, but nodes.names has {}", it->size(), n));
    return &*it;
  }

  void read_dense_nodes(const Json& nodes, std::vector<ConnectomeNode>& out) const {
    const auto names = nodes.find("names");
    if (names == nodes.end() || !names->is_array())
      fail("nodes.names", "is missing or not an array (the dense layout needs names, X, Y and Z)");
    const size_t n = names->size();
    if (n == 0) fail("nodes.names", "is empty: a connectome needs at least one node");
    if (n > UINT32_MAX) fail("nodes.names", fmt::format("has {} nodes, too many", n));
    const Json& x = *dense_array(nodes, "X", n, true);
    const Json& y = *dense_array(nodes, "Y", n, true);
    const Json& z = *dense_array(nodes, "Z", n, true);
    const Json* color = dense_array(nodes, "Color", n, false);
    const Json* size = dense_array(nodes, "Size", n, false);
    out.resize(n);
    for (size_t i = 0; i < n; ++i) {
      ConnectomeNode& node = out[i];
      node.name = text((*names)[i], {"nodes.names", i});
      // MNI RAS mm to world LPS.
      node.position = {-number(x[i], Field{"nodes.X", i}), -number(y[i], Field{"nodes.Y", i}),
                       number(z[i], Field{"nodes.Z", i})};
      if (color) node.value = number((*color)[i], Field{"nodes.Color", i});
      if (size) node.size = number((*size)[i], Field{"nodes.Size", i});
    }
    if (!color)
      notes_.push_back(fmt::format("{}: nodes.Color is missing: every node's value is 0", what_));
    if (!size)
      notes_.push_back(fmt::format("{}: nodes.Size is missing: every node's size is 1", what_));
  }

  std::vector<ConnectomeEdge> read_dense_edges(const Json& edges, size_t n) const {
    if (!edges.is_array())
      fail("edges", fmt::format("is {}, not an array of {} x {} numbers", shown(edges), n, n));
    if (edges.size() != n * n)
      fail("edges", fmt::format("has {} values, but {} nodes need a {} x {} matrix of {} "
                                "(row by row)",
                                edges.size(), n, n, n, n * n));
    check_memory(sizeof(float) * n * n, what_ + " (its edge matrix)");
    std::vector<float> matrix(n * n);
    for (size_t i = 0; i < n * n; ++i) matrix[i] = number(edges[i], Field{"edges", i, {}, n});
    if (const std::optional<MatrixEntry> e = first_asymmetry(matrix, n))
      notes_.push_back(fmt::format(
          "{}: the edge matrix is not symmetric (row {}, column {} is {}, but row {}, column {} "
          "is {}, from 0): its upper triangle is used, as NiiVue does",
          what_, e->row, e->column, matrix[e->row * n + e->column], e->column, e->row,
          matrix[e->column * n + e->row]));
    return triangle_edges(matrix, n, true);
  }

  void read_sparse_nodes(const Json& nodes, std::vector<ConnectomeNode>& out) const {
    const size_t n = nodes.size();
    if (n == 0) fail("nodes", "is empty: a connectome needs at least one node");
    if (n > UINT32_MAX) fail("nodes", fmt::format("has {} nodes, too many", n));
    out.resize(n);
    size_t unnamed = 0, without_color = 0, without_size = 0;
    for (size_t i = 0; i < n; ++i) {
      const Json& item = nodes[i];
      if (!item.is_object())
        fail(Field{"nodes", i}.str(), fmt::format("is {}, not a node object", shown(item)));
      const auto field = [&](const char* key) -> const Json* {
        const auto it = item.find(key);
        return it == item.end() || it->is_null() ? nullptr : &*it;
      };
      ConnectomeNode& node = out[i];
      float ras[3];
      for (int axis = 0; axis < 3; ++axis) {
        const char* key = axis == 0 ? "x" : axis == 1 ? "y" : "z";
        const Json* v = field(key);
        if (!v) fail(Field{"nodes", i, key}.str(), "is missing");
        ras[axis] = number(*v, {"nodes", i, key});
      }
      node.position = {-ras[0], -ras[1], ras[2]};  // MNI RAS mm to world LPS
      if (const Json* v = field("name"))
        node.name = text(*v, {"nodes", i, "name"});
      else
        ++unnamed;
      if (const Json* v = field("colorValue"))
        node.value = number(*v, {"nodes", i, "colorValue"});
      else
        ++without_color;
      if (const Json* v = field("sizeValue"))
        node.size = number(*v, {"nodes", i, "sizeValue"});
      else
        ++without_size;
    }
    if (unnamed) notes_.push_back(fmt::format("{}: {} nodes have no name", what_, unnamed));
    if (without_color)
      notes_.push_back(
          fmt::format("{}: {} nodes have no colorValue: their value is 0", what_, without_color));
    if (without_size)
      notes_.push_back(
          fmt::format("{}: {} nodes have no sizeValue: their size is 1", what_, without_size));
  }

  std::vector<ConnectomeEdge> read_sparse_edges(const Json& edges, size_t n) const {
    if (!edges.is_array())
      fail("edges", fmt::format("is {}, not an array of edge objects", shown(edges)));
    std::vector<ConnectomeEdge> out;
    out.reserve(edges.size());
    std::unordered_set<uint64_t> seen;
    size_t loops = 0, repeated = 0;
    for (size_t i = 0; i < edges.size(); ++i) {
      const Json& item = edges[i];
      if (!item.is_object())
        fail(Field{"edges", i}.str(),
             fmt::format("is {}, not an edge object (first, second, colorValue)", shown(item)));
      const auto field = [&](const char* key) -> const Json& {
        const auto it = item.find(key);
        if (it == item.end()) fail(Field{"edges", i, key}.str(), "is missing");
        return *it;
      };
      uint32_t a = node_index(field("first"), n, {"edges", i, "first"});
      uint32_t b = node_index(field("second"), n, {"edges", i, "second"});
      const float weight = number(field("colorValue"), {"edges", i, "colorValue"});
      if (a == b) {
        ++loops;
        continue;
      }
      if (a > b) std::swap(a, b);
      if (!seen.insert(uint64_t{a} << 32 | b).second) {
        ++repeated;
        continue;
      }
      if (weight != 0.0f) out.push_back({a, b, weight});  // NiiVue draws no edge of weight 0
    }
    if (loops)
      notes_.push_back(fmt::format("{}: {} edges join a node to itself: dropped", what_, loops));
    if (repeated)
      notes_.push_back(
          fmt::format("{}: {} edges repeat a pair of nodes named before: the first of each is kept",
                      what_, repeated));
    return out;
  }

  // FreeSurfer's point set (Freeview's .json), which NiiVue also reads as a connectome: nodes
  // at points[i].coordinates, named by their first comment, without edges.
  Connectome read_point_set(const Json& doc) const {
    const auto space = doc.find("vox2ras");
    if (space == doc.end() || space->is_null())
      notes_.push_back(
          fmt::format("{}: the point set names no vox2ras: its coordinates are taken "
                      "as scanner RAS, as NiiVue does",
                      what_));
    else if (*space != "scanner_ras")
      fail("vox2ras", fmt::format("is {}: only point sets in scanner RAS (\"scanner_ras\") are "
                                  "read; tkreg coordinates need the volume they belong to",
                                  shown(*space)));
    const auto points = doc.find("points");
    if (points == doc.end() || !points->is_array())
      fail("points", "is missing or not an array (a FreeSurfer point set)");
    const size_t n = points->size();
    if (n == 0) fail("points", "is empty: a connectome needs at least one node");
    if (n > UINT32_MAX) fail("points", fmt::format("has {} points, too many", n));
    Connectome out;
    out.nodes.resize(n);
    for (size_t i = 0; i < n; ++i) {
      const Json& point = (*points)[i];
      const auto c = point.is_object() ? point.find("coordinates") : point.end();
      if (!point.is_object() || c == point.end() || !c->is_object())
        fail(Field{"points", i, "coordinates"}.str(), "is missing or not an object");
      float ras[3];
      for (int axis = 0; axis < 3; ++axis) {
        const char* key = axis == 0 ? "x" : axis == 1 ? "y" : "z";
        const auto v = c->find(key);
        if (v == c->end()) fail(Field{"points", i, "coordinates"}.str() + "." + key, "is missing");
        ras[axis] = number(*v, {"points", i, key});
      }
      out.nodes[i].position = {-ras[0], -ras[1], ras[2]};  // scanner RAS mm to world LPS
      out.nodes[i].value = 1.0f;                           // NiiVue's colour and size for points
      if (const auto comments = point.find("comments");
          comments != point.end() && comments->is_array() && !comments->empty() &&
          (*comments)[0].is_object() && (*comments)[0].contains("text"))
        out.nodes[i].name = text((*comments)[0]["text"], {"points", i, "comments[0].text"});
    }
    notes_.push_back(fmt::format("{}: a FreeSurfer point set: {} nodes, no edges", what_, n));
    return out;
  }

  std::string what_;
  std::vector<std::string>& notes_;
};

}  // namespace

Connectome read_jcon(const std::filesystem::path& file, std::vector<std::string>& notes) {
  return JconReader(file, notes).read(file);
}

}  // namespace imx::detail
