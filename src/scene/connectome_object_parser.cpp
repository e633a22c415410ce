// Parser for a "connectome" object: a connectome file (NiiVue's JSON, BrainNet Viewer's .node
// and .edge), its transform, and the display fields that override the file's. It becomes a
// streamline object whose tubes are the connectome's spheres and tubes (scene.hpp).
#include <fmt/format.h>
#include <glm/glm.hpp>

#include "intermix/error.hpp"
#include "io/connectome/brainnet.hpp"
#include "io/streamlines/streamline_formats.hpp"
#include "scene/scene_parsers.hpp"
#include "tubes/connectome_primitives.hpp"
#include "tubes/tube_cache.hpp"

namespace imx::scene_json {
namespace {

// The file's nodes and edges: a .node with the .edge "edges" names, or any connectome file.
Connectome read_connectome(const JsonReader& src, const std::string& name, SceneContext& context) {
  src.check_keys({"file", "edges"});
  JsonReader file_reader = src.get("file");
  const std::filesystem::path path = context.resolve_file(file_reader);
  std::optional<std::filesystem::path> edges;
  if (auto e = src.find("edges")) {
    if (path.extension() != ".node")
      e->fail("\"edges\" (a BrainNet .edge file) goes with a BrainNet .node \"file\"");
    edges = context.resolve_file(*e);
  }
  return file_reader.reading(path.string(), [&] {
    std::vector<std::string> notes;
    Connectome c = edges ? detail::read_brainnet(path, edges, notes)
                         : detail::read_connectome_file(path, notes);
    for (const std::string& note : notes)
      context.notes.push_back(fmt::format("connectome '{}': {}", name, note));
    return c;
  });
}

// A colour map the file names (NiiVue's field `field`), refused naming the file and field.
Colormap file_colormap(const std::string& value, const char* field, const JsonReader& file,
                       const std::filesystem::path& path) {
  if (std::optional<Colormap> map = connectome_colormap(value)) return *map;
  file.fail(fmt::format("{}: \"{}\" is \"{}\", not a colour map intermix has ({})", path.string(),
                        field, value, connectome_colormap_names()));
}

Colormap object_colormap(const JsonReader& v) {
  if (std::optional<Colormap> map = connectome_colormap(v.string())) return *map;
  v.fail(fmt::format("{} is not a colour map intermix has ({})", v.text(),
                     connectome_colormap_names()));
}

// The look: each field from the object, else from the file's style, else NiiVue's default.
ConnectomeLook resolve_look(const JsonReader& r, const ConnectomeStyle& style,
                            const JsonReader& file, const std::filesystem::path& path) {
  ConnectomeLook look;
  auto number = [&](const char* key, const std::optional<float>& from_file, float& out,
                    Range range) {
    if (auto v = r.find(key))
      out = static_cast<float>(v->number(range));
    else if (from_file)
      out = *from_file;
  };
  auto colormap = [&](const char* key, const char* niivue_field,
                      const std::optional<std::string>& from_file, Colormap& out) {
    if (auto v = r.find(key))
      out = object_colormap(*v);
    else if (from_file)
      out = file_colormap(*from_file, niivue_field, file, path);
  };
  number("node_scale", style.node_scale, look.node_scale, Range::non_negative());
  number("node_min", style.node_min_color, look.node_min, Range::any());
  number("node_max", style.node_max_color, look.node_max, Range::any());
  number("edge_scale", style.edge_scale, look.edge_scale, Range::non_negative());
  number("edge_min", style.edge_min, look.edge_min, Range::any());
  number("edge_max", style.edge_max, look.edge_max, Range::any());
  colormap("node_colormap", "nodeColormap", style.node_colormap, look.node_colormap);
  colormap("node_colormap_negative", "nodeColormapNegative", style.node_colormap_negative,
           look.node_colormap_negative);
  colormap("edge_colormap", "edgeColormap", style.edge_colormap, look.edge_colormap);
  colormap("edge_colormap_negative", "edgeColormapNegative", style.edge_colormap_negative,
           look.edge_colormap_negative);
  return look;
}

}  // namespace

StreamlineObject parse_connectome_object(const JsonReader& r, SceneContext& context) {
  r.check_keys({"name", "type", "source", "transform", "node_scale", "node_min", "node_max",
                "edge_scale", "edge_min", "edge_max", "node_colormap", "node_colormap_negative",
                "edge_colormap", "edge_colormap_negative", "opacity", "shading", "thickness",
                "visible"});
  StreamlineObject o;
  o.name = r.get("name").string();
  glm::dmat4 transform(1.0);
  if (auto t = r.find("transform")) transform = parse_transform(*t, context);
  if (auto v = r.find("opacity"))
    o.opacity = static_cast<float>(v->number(Range::closed(0.0, 1.0)));
  if (auto v = r.find("shading")) o.shading = parse_shading(*v);
  if (auto v = r.find("thickness")) o.thickness = parse_thickness(*v);
  if (!parse_visible(r)) o.opacity = 0.0f;
  const JsonReader source = r.get("source");
  auto connectome = std::make_shared<Connectome>(read_connectome(source, o.name, context));
  for (ConnectomeNode& node : connectome->nodes)
    node.position = glm::vec3(transform * glm::dvec4(glm::dvec3(node.position), 1.0));
  const JsonReader file = source.get("file");
  o.connectome_look = resolve_look(r, connectome->style, file, context.resolve_file(file));
  const ConnectomeLook& look = o.connectome_look;
  const ConnectomePrimitives shown = connectome_primitives(*connectome, look);
  // Thresholds nobody chose that hide something: say so (BrainNet files give none).
  const bool own_edge_min = r.has("edge_min") || connectome->style.edge_min;
  if (shown.hidden_edges > 0 && !own_edge_min)
    context.notes.push_back(fmt::format(
        "connectome '{}': {} of {} edges have |weight| below NiiVue's default edge_min {} and "
        "are not drawn (set \"edge_min\")",
        o.name, shown.hidden_edges, connectome->edges.size(), look.edge_min));
  const bool own_node_min = r.has("node_min") || connectome->style.node_min_color;
  if (shown.hidden_nodes > 0 && !own_node_min)
    context.notes.push_back(fmt::format(
        "connectome '{}': {} of {} nodes have a value below NiiVue's default node_min {} and "
        "are not drawn (set \"node_min\")",
        o.name, shown.hidden_nodes, connectome->nodes.size(), look.node_min));
  // What bounds and depth ranges see: the node centres, grown by the largest radius.
  auto centres = std::make_shared<Streamlines>();
  centres->points.reserve(connectome->nodes.size());
  for (const ConnectomeNode& node : connectome->nodes) centres->points.push_back(node.position);
  o.streamlines = std::move(centres);
  o.radius = shown.largest_radius;
  o.connectome = std::move(connectome);
  o.cache = make_tube_cache();
  return o;
}

}  // namespace imx::scene_json
