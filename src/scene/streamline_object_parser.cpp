// Parser for a "streamlines" object: a tractogram file and its values, its transform, and how
// its tubes look and which of them show.
#include <fmt/format.h>
#include <tbb/parallel_for.h>
#include <glm/glm.hpp>

#include "intermix/error.hpp"
#include "intermix/io.hpp"
#include "intermix/limits.hpp"
#include "io/streamlines/streamline_formats.hpp"
#include "scene/scene_parsers.hpp"
#include "scene/world_space.hpp"
#include "tubes/tube_cache.hpp"

namespace imx::scene_json {
namespace {

constexpr size_t kMaxClipPlanes = 64;  // each is a test per tube crossing

const std::vector<std::pair<std::string, StreamlineColouring>> kColourings = {
    {"direction", StreamlineColouring::direction},
    {"streamline_direction", StreamlineColouring::streamline_direction},
    {"fixed", StreamlineColouring::fixed},
    {"point_value", StreamlineColouring::point_value},
    {"streamline_value", StreamlineColouring::streamline_value},
    {"group", StreamlineColouring::group}};

// The tractogram a "source" names, read once per file and list of value files.
std::shared_ptr<const Streamlines> load_streamlines(const JsonReader& src, const std::string& name,
                                                    SceneContext& context) {
  if (!context.given_streamlines.empty() && src.json().is_object() && src.has("$streamlines")) {
    src.check_keys({"$streamlines"});
    JsonReader id = src.get("$streamlines");
    auto it = context.given_streamlines.find(id.string());
    if (it == context.given_streamlines.end())
      id.fail(id.text() + " is not a set of streamlines of this scene");
    return it->second;
  }
  if (src.json().is_object() && ((!context.given_volumes.empty() && src.has("$volume")) ||
                                 (!context.given_meshes.empty() && src.has("$mesh"))))
    src.fail(fmt::format("is a {} the program gave, not streamlines",
                         src.has("$volume") ? "volume" : "mesh"));
  src.check_keys({"file", "values"});
  JsonReader file_reader = src.get("file");
  const std::filesystem::path path = context.resolve_file(file_reader);
  std::vector<std::filesystem::path> values;
  std::string key = "streamlines:" + path.string();
  if (auto v = src.find("values"))
    for (const JsonReader& e : v->elements()) {
      values.push_back(context.resolve_file(e));
      key.append("\n").append(values.back().string());
    }
  context.used.insert(key);
  if (auto it = context.streamlines.find(key); it != context.streamlines.end()) return it->second;
  auto read = file_reader.reading(path.string(), [&] {
    std::vector<std::string> notes;
    auto s = std::make_shared<const Streamlines>(detail::read_streamline_file(path, values, notes));
    for (const std::string& note : notes)
      context.notes.push_back(fmt::format("streamlines '{}': {}", name, note));
    return s;
  });
  context.streamlines.emplace(key, read);
  return read;
}

// The same streamlines moved by `transform` (a copy; the identity shares the file's).
std::shared_ptr<const Streamlines> placed(std::shared_ptr<const Streamlines> s,
                                          const glm::dmat4& transform) {
  if (transform == glm::dmat4(1.0)) return s;
  auto moved = std::make_shared<Streamlines>(*s);
  tbb::parallel_for(size_t(0), moved->points.size(), [&](size_t i) {
    moved->points[i] = glm::vec3(transform * glm::dvec4(glm::dvec3(moved->points[i]), 1.0));
  });
  return moved;
}

StreamlineRegion parse_region(const JsonReader& r, SceneContext& context) {
  r.check_keys({"sphere", "label_map", "label", "mesh", "avoid"});
  StreamlineRegion region;
  if (auto v = r.find("avoid")) region.avoid = v->boolean();
  const int shapes = int(r.has("sphere")) + int(r.has("label_map")) + int(r.has("mesh"));
  if (shapes != 1) r.fail("needs one of \"sphere\", \"label_map\" (with \"label\") or \"mesh\"");
  if (auto v = r.find("sphere")) {
    v->check_keys({"center", "radius"});
    const std::vector<double> c = v->get("center").numbers(3);
    region.center = to_lps({c[0], c[1], c[2]}, context.world_space);
    region.radius = v->get("radius").number(Range::length());
  } else if (auto v = r.find("label_map")) {
    v->check_keys({"file"});
    JsonReader file = v->get("file");
    const std::filesystem::path path = context.resolve_file(file);
    region.shape = StreamlineRegion::Shape::label;
    region.labels = file.reading(
        path.string(), [&] { return std::make_shared<const VolumeData>(read_volume(path)); });
    region.label = r.get("label").integer(-(1 << 30), 1 << 30);
  } else {
    JsonReader mesh = r.get("mesh");
    mesh.check_keys({"file"});
    JsonReader file = mesh.get("file");
    const std::filesystem::path path = context.resolve_file(file);
    region.shape = StreamlineRegion::Shape::mesh;
    region.mesh = file.reading(
        path.string(), [&] { return std::make_shared<const Mesh>(read_mesh_file(path).mesh); });
  }
  if (r.has("label") && region.shape != StreamlineRegion::Shape::label)
    r.get("label").fail("\"label\" goes with \"label_map\"");
  return region;
}

// A tractogram whose tubes would exceed the memory budget is decimated, not refused: the
// smallest stride whose tubes fit, with a note (the streamlines' own points stay: they must fit).
void fit_stride_to_budget(StreamlineObject& o, SceneContext& context) {
  const Streamlines& s = *o.streamlines;
  const uint64_t budget = input_limits().max_memory, points = s.points.size();
  const uint64_t segments = points - std::min<uint64_t>(points, s.count());
  auto fits = [&](uint64_t stride) {
    return tube_bytes(s.count() / stride, segments / stride) <= budget;
  };
  uint64_t stride = static_cast<uint64_t>(o.stride);
  if (fits(stride) || !fits(s.count() + 1)) return;
  const uint64_t full = tube_bytes(s.count() / stride, segments / stride);
  while (!fits(stride)) ++stride;
  o.stride = static_cast<int>(stride);
  context.notes.push_back(fmt::format(
      "streamlines '{}': tubes for all {} streamlines need {}, more than the memory budget of {} "
      "(--max-memory): one in {} is drawn (\"stride\": {})",
      o.name, s.count(), format_bytes(full), format_bytes(budget), stride, stride));
}

}  // namespace

StreamlineObject parse_streamline_object(const JsonReader& r, SceneContext& context) {
  r.check_keys({"name",    "type",        "source",     "transform", "radius",    "color_by",
                "color",   "value",       "colormap",   "range",     "opacity",   "group_opacity",
                "shading", "stride",      "min_length", "regions",   "thickness", "visible",
                "sides",   "clip_planes", "clip"});
  StreamlineObject o;
  o.name = r.get("name").string();
  glm::dmat4 transform(1.0);
  if (auto t = r.find("transform")) transform = parse_transform(*t, context);
  if (auto v = r.find("radius")) o.radius = v->number(Range::length());
  if (auto v = r.find("color")) o.color = v->color();
  if (auto v = r.find("color_by")) {
    const std::string chosen = v->choice(
        {"direction", "streamline_direction", "fixed", "point_value", "streamline_value", "group"});
    for (const auto& [n, c] : kColourings)
      if (n == chosen) o.colouring = c;
  } else if (r.has("color")) {
    o.colouring = StreamlineColouring::fixed;
  }
  if (auto v = r.find("value")) o.value = v->string();
  const bool by_value = o.colouring == StreamlineColouring::point_value ||
                        o.colouring == StreamlineColouring::streamline_value;
  if (by_value && o.value.empty())
    r.fail(fmt::format(
        "\"color_by\": \"{}\" needs \"value\": the name of the values",
        o.colouring == StreamlineColouring::point_value ? "point_value" : "streamline_value"));
  if (auto v = r.find("colormap")) o.colormap = parse_colormap(*v);
  if (auto v = r.find("range")) {
    const std::vector<double> range = v->numbers(2);
    if (!(range[0] < range[1])) v->fail("needs [low, high] with low < high");
    o.range = glm::dvec2(range[0], range[1]);
  }
  if (auto v = r.find("opacity"))
    o.opacity = static_cast<float>(v->number(Range::closed(0.0, 1.0)));
  if (auto v = r.find("shading")) o.shading = parse_shading(*v);
  if (auto v = r.find("stride")) o.stride = v->integer(1, 1 << 30);
  if (auto v = r.find("min_length")) o.min_length = v->number(Range::closed(0.0, 1e9));
  if (auto v = r.find("thickness")) o.thickness = parse_thickness(*v);
  if (auto v = r.find("regions"))
    for (const JsonReader& e : v->elements()) o.regions.push_back(parse_region(e, context));
  if (auto v = r.find("clip_planes")) {
    if (v->size() > kMaxClipPlanes)
      v->fail(
          fmt::format("{} clip planes; streamlines take at most {}", v->size(), kMaxClipPlanes));
    o.clip_planes = parse_clip_planes(*v, context.world_space);  // as a volume's, world space
  }
  // "clip" names meshes, which may come later in the file: parse_clip_meshes reads it.
  if (auto v = r.find("sides"))
    v->integer(3, 64);  // the VTK peer's tube sides; tubes here are round
  if (!parse_visible(r)) o.opacity = 0.0f;
  const std::shared_ptr<const Streamlines> read =
      load_streamlines(r.get("source"), o.name, context);
  if (auto v = r.find("group_opacity")) {
    o.group_opacity.assign(read->groups.size(), o.opacity);
    for (const auto& [group, value] : v->json().items()) {
      const JsonReader entry = v->get(group);
      size_t g = 0;
      while (g < read->groups.size() && read->groups[g].name != group) ++g;
      if (g == read->groups.size())
        entry.fail(fmt::format("the streamlines have no group '{}'", group));
      o.group_opacity[g] = static_cast<float>(entry.number(Range::closed(0.0, 1.0)));
    }
  }
  // One placed copy and one tube cache per source and transform, kept while the document
  // uses them, so that an edit of the look does not rebuild the tubes.
  std::string key = fmt::format("placed-streamlines:{}", static_cast<const void*>(read.get()));
  for (int c = 0; c < 4; ++c)
    for (int row = 0; row < 4; ++row) key += fmt::format(" {}", transform[c][row]);
  key += " " + o.name;
  context.used.insert(key);
  auto [it, fresh] = context.placed_streamlines.try_emplace(key);
  if (fresh) it->second = {placed(read, transform), make_tube_cache()};
  o.streamlines = it->second.first;
  o.cache = it->second.second;
  fit_stride_to_budget(o, context);
  return o;
}

}  // namespace imx::scene_json
