// Parser for the scene's "csg" block: an expression over dvr volumes, closed meshes and
// streamline objects (the inside of their tubes).
#include <algorithm>
#include <charconv>
#include <map>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include <fmt/format.h>

#include "core/edit_distance.hpp"
#include "io/mesh/mesh_topology.hpp"
#include "scene/label_map_parser.hpp"
#include "scene/scene_parsers.hpp"

namespace imx::scene_json {
namespace {

constexpr size_t kMaxPrimitives = 64;  // one bit each in a uint64 mask
constexpr size_t kMaxVolumes = 16;     // the volumes one ray can march at once
constexpr int kMaxDepth = 256;         // operators nested; bounds the recursion here and later

const char* style_name(VolumeStyle style) {
  switch (style) {
    case VolumeStyle::dvr:
      return "dvr";
    case VolumeStyle::iso:
      return "iso";
    case VolumeStyle::mip:
      return "mip";
    case VolumeStyle::minip:
      return "minip";
    case VolumeStyle::xray:
      return "xray";
  }
  return "?";
}

const char* presence_name(CsgPresence p) {
  return p == CsgPresence::region ? "region" : "opacity";
}

std::string plural(size_t n, const char* word) {
  return fmt::format("{} {}{}", n, word, n == 1 ? "" : "s");
}

// Builds the node arena, children before their parents, while checking every leaf.
class CsgBuilder {
 public:
  explicit CsgBuilder(Scene& scene) : scene_(scene) {
    for (const ObjectRef& ref : scene.order) {
      names_.push_back(name_of(ref));
      by_name_.emplace(names_.back(), ref);
    }
  }

  CsgExpression build(const JsonReader& root) {
    expression_.root = node(root, 0);
    return std::move(expression_);
  }

 private:
  struct Seen {
    CsgPresence presence;
    std::string path;                  // where the object first appears
    std::optional<std::string> label;  // "seg:liver": the label it stands for
    std::string as;                    // how the expression names it there
  };

  // A label volume standing for one of its labels ("seg:liver", by name or value): its map
  // shows that label alone, so that it is present (and drawn) only where that label wins.
  void keep_only_label(const ObjectRef& ref, const std::string& name, const std::string& label,
                       const JsonReader& at) {
    if (ref.kind != ObjectKind::volume || !scene_.volumes[ref.index].labels)
      at.fail(fmt::format("'{}' is not a label volume: \"{}:{}\" names a label of one", name, name,
                          label));
    VolumeObject& volume = scene_.volumes[ref.index];
    if (primitives_.count({ref.kind, ref.index})) return;  // done at its first appearance
    auto map = std::make_shared<LabelMap>(*volume.labels);
    std::vector<std::string> names;
    std::optional<int32_t> value;
    for (const LabelEntry& e : map->entries) {
      names.push_back(e.name);
      if (e.name == label || std::to_string(e.value) == label) value = e.value;
    }
    int32_t number = 0;
    const auto [end, error] = std::from_chars(label.data(), label.data() + label.size(), number);
    if (!value && error == std::errc() && end == label.data() + label.size())
      value = number;  // a palette label the table does not list
    if (!value)
      at.fail(fmt::format("'{}' has no label '{}'{}", name, label, did_you_mean(label, names)));
    LabelEntry kept = label_entry(*map, *value);
    kept.visible = true;
    map->entries = {kept};
    map->palette_unlisted = false;
    volume.labels = std::move(map);
  }

  std::string name_of(const ObjectRef& ref) const { return object_name(scene_, ref); }

  // `level` counts the operators above r; checking it before descending keeps a hostile file
  // from exhausting the stack.
  int node(const JsonReader& r, int level) {
    if (r.json().is_string()) return leaf(r, nullptr, r);
    if (!r.json().is_object())
      r.fail(
          "expected an object name, {\"object\": name, \"presence\": ...} or {\"op\": ...}, "
          "got " +
          r.describe());
    r.check_keys({"op", "a", "b", "of", "object", "presence"});
    const bool is_leaf = r.has("object");
    if (is_leaf && (r.has("op") || r.has("a") || r.has("b") || r.has("of")))
      r.fail(
          "a node is either a primitive {\"object\": ...} or an operator {\"op\": ...}, "
          "not both");
    if (is_leaf) {
      std::optional<JsonReader> presence = r.find("presence");
      return leaf(r.get("object"), presence ? &*presence : nullptr, r);
    }
    if (auto p = r.find("presence"))
      p->fail("only a primitive {\"object\": name, \"presence\": ...} has a presence");
    return operation(r, level + 1);
  }

  int operation(const JsonReader& r, int level) {
    if (level > kMaxDepth) r.fail(fmt::format("nesting deeper than {} levels", kMaxDepth));
    const std::string name = r.get("op").choice({"union", "intersection", "difference"});
    const CsgOp op = name == "union"          ? CsgOp::union_of
                     : name == "intersection" ? CsgOp::intersection
                                              : CsgOp::difference;
    const bool binary = r.has("a") || r.has("b");
    if (binary && r.has("of")) r.fail("give either \"a\" and \"b\" or \"of\", not both");
    if (binary) {
      int a = node(r.get("a"), level);
      int b = node(r.get("b"), level);
      return join(op, a, b, r);
    }
    if (!r.has("of")) r.fail("needs operands: \"a\" and \"b\", or \"of\" (a list of at least 2)");
    JsonReader of = r.get("of");
    if (!of.json().is_array()) of.fail("expected a list of operands, got " + of.describe());
    if (of.size() < 2) of.fail(fmt::format("needs at least 2 operands, got {}", of.size()));
    // Union and intersection fold left-deep; so does difference: ((x - y) - z) - ...
    int folded = node(of.at(0), level);
    for (size_t i = 1; i < of.size(); ++i) {
      JsonReader operand = of.at(i);
      folded = join(op, folded, node(operand, level), operand);
    }
    return folded;
  }

  int join(CsgOp op, int a, int b, const JsonReader& at) {
    const int height = 1 + std::max(heights_[a], heights_[b]);
    if (height > kMaxDepth)
      at.fail(
          fmt::format("nesting deeper than {} levels (an \"of\" list of n operands nests "
                      "n - 1 levels)",
                      kMaxDepth));
    CsgNode n;
    n.op = op;
    n.a = a;
    n.b = b;
    return add(n, height);
  }

  int add(const CsgNode& n, int height) {
    expression_.nodes.push_back(n);
    heights_.push_back(height);
    return static_cast<int>(expression_.nodes.size() - 1);
  }

  // A primitive named at `name_at`, in the node at `node_at` (the same reader for a bare name).
  int leaf(const JsonReader& name_at, const JsonReader* presence_at, const JsonReader& node_at) {
    std::string name = name_at.string();
    // "seg:liver" (or "seg:3"): one label of label volume seg, present only where it wins.
    std::optional<std::string> label;
    if (const size_t colon = name.rfind(':'); !by_name_.count(name) && colon != std::string::npos &&
                                              by_name_.count(name.substr(0, colon))) {
      label = name.substr(colon + 1);
      name.resize(colon);
    }
    auto found = by_name_.find(name);
    if (found == by_name_.end())
      name_at.fail(fmt::format("no object named '{}'{}", name, did_you_mean(name, names_)));
    const ObjectRef ref = found->second;
    if (label) keep_only_label(ref, name, *label, name_at);
    if (ref.kind == ObjectKind::plane)
      name_at.fail(fmt::format(
          "'{}' is a plane; CSG primitives are volumes and closed meshes, and streamlines", name));
    if (ref.kind == ObjectKind::streamlines && scene_.streamlines[ref.index].connectome)
      name_at.fail(fmt::format(
          "'{}' is a connectome; CSG primitives are volumes and closed meshes, and streamlines",
          name));
    if (ref.kind == ObjectKind::volume && scene_.volumes[ref.index].style != VolumeStyle::dvr)
      name_at.fail(
          fmt::format("'{}' is a volume of style {}; CSG primitives are dvr volumes and "
                      "closed meshes",
                      name, style_name(scene_.volumes[ref.index].style)));

    CsgPresence presence =
        ref.kind == ObjectKind::volume ? CsgPresence::opacity : CsgPresence::region;
    if (presence_at) {
      presence = presence_at->choice({"opacity", "region"}) == "region" ? CsgPresence::region
                                                                        : CsgPresence::opacity;
      if (ref.kind == ObjectKind::mesh && presence == CsgPresence::opacity)
        presence_at->fail(fmt::format(
            "mesh '{}' can only have presence \"region\" (a mesh is present wherever it "
            "encloses the point, whatever its material)",
            name));
      if (ref.kind == ObjectKind::streamlines && presence == CsgPresence::opacity)
        presence_at->fail(fmt::format(
            "streamlines '{}' can only have presence \"region\" (tubes are present wherever "
            "they enclose the point, whatever their opacity)",
            name));
    }

    const std::pair<ObjectKind, int> key{ref.kind, ref.index};
    if (auto seen = primitives_.find(key); seen != primitives_.end()) {
      if (seen->second.label != label)
        name_at.fail(
            fmt::format("'{}' is at {} as '{}'; one volume object is one primitive: for "
                        "another of its labels add another object of the same file",
                        name, seen->second.path, seen->second.as));
      if (seen->second.presence != presence)
        (presence_at ? *presence_at : name_at)
            .fail(fmt::format("'{}' has presence {} at {}; an object has one presence in the "
                              "expression",
                              name, presence_name(seen->second.presence), seen->second.path));
    } else {
      admit(ref, name, node_at);
      primitives_.emplace(key, Seen{presence, node_at.path(), label, name_at.string()});
    }

    CsgNode n;
    n.op = CsgOp::primitive;
    n.object = ref;
    n.presence = presence;
    return add(n, 0);
  }

  // Checks a primitive seen for the first time against the limits and, for a mesh, its
  // topology; an inward-facing mesh is turned outward so that "inside" is unambiguous.
  void admit(const ObjectRef& ref, const std::string& name, const JsonReader& at) {
    if (primitives_.size() == kMaxPrimitives)
      at.fail(fmt::format("at most {} primitives; '{}' is the {}th", kMaxPrimitives, name,
                          kMaxPrimitives + 1));
    if (ref.kind == ObjectKind::volume) {
      if (volumes_ == kMaxVolumes)
        at.fail(fmt::format("at most {} volumes (a ray holds {}); '{}' is the {}th volume",
                            kMaxVolumes, kMaxVolumes, name, kMaxVolumes + 1));
      ++volumes_;
      return;
    }
    if (ref.kind == ObjectKind::streamlines) return;  // tubes are closed: round, capped ends
    MeshObject& mesh = scene_.meshes[ref.index];
    const MeshTopology topology = check_closed(*mesh.mesh);
    if (topology.open_edges > 0)
      at.fail(fmt::format("mesh '{}' is not closed: {}", name,
                          plural(topology.open_edges, "open edge")));
    if (topology.unpaired_edges > 0)
      at.fail(fmt::format("mesh '{}' is not consistently wound: {} without its reverse", name,
                          plural(topology.unpaired_edges, "directed edge")));
    // Each MeshObject owns the mesh its transform produced, so this flips no other object.
    if (topology.signed_volume < 0.0) mesh.mesh = std::make_shared<const Mesh>(flipped(*mesh.mesh));
  }

  Scene& scene_;
  std::vector<std::string> names_;
  std::map<std::string, ObjectRef> by_name_;
  std::map<std::pair<ObjectKind, int>, Seen> primitives_;
  size_t volumes_ = 0;
  std::vector<int> heights_;  // per node: operators on the longest path down to a leaf
  CsgExpression expression_;
};

}  // namespace

std::optional<CsgExpression> parse_csg(const JsonReader& r, Scene& scene) {
  if (r.json().is_null()) return std::nullopt;
  return CsgBuilder(scene).build(r);
}

void check_interiors(const std::vector<JsonReader>& objects, const Scene& scene) {
  std::vector<bool> primitive(scene.meshes.size(), false);
  if (scene.csg)
    for (const CsgNode& n : scene.csg->nodes)
      if (n.op == CsgOp::primitive && n.object.kind == ObjectKind::mesh)
        primitive[n.object.index] = true;
  for (size_t i = 0; i < scene.order.size() && i < objects.size(); ++i) {
    const ObjectRef& ref = scene.order[i];
    if (ref.kind != ObjectKind::mesh || !scene.meshes[ref.index].interior || primitive[ref.index])
      continue;
    const std::string& name = scene.meshes[ref.index].name;
    objects[i]
        .get("interior")
        .fail(scene.csg
                  ? fmt::format("only CSG primitives have an interior (mesh '{}' is not in the "
                                "csg expression)",
                                name)
                  : fmt::format("only CSG primitives have an interior (the scene has no csg "
                                "expression for mesh '{}' to be in)",
                                name));
  }
}

}  // namespace imx::scene_json
