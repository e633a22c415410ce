// ViewerState: a viewer session's scene as imx::Scene and as scene-file JSON, and the edit
// messages that change both together.
#include "server/viewer_state.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <fstream>
#include <limits>
#include <map>
#include <optional>
#include <sstream>
#include <string_view>
#include <variant>

#include <fmt/format.h>
#include <glm/glm.hpp>

#include "annotate/colour_bar.hpp"
#include "annotate/scene_colour_bars.hpp"
#include "core/colour.hpp"
#include "core/edit_distance.hpp"
#include "intermix/error.hpp"
#include "presets/colormap.hpp"
#include "presets/volume_presets.hpp"
#include "scene/overrides.hpp"
#include "scene/scene_parsers.hpp"
#include "scene/strict_json.hpp"
#include "scene/world_space.hpp"
#include "server/annotation_messages.hpp"
#include "server/label_list.hpp"
#include "volume/value_sample.hpp"

namespace imx::server {
namespace {

using scene_json::JsonReader;
using scene_json::Range;
using Json = nlohmann::json;

// Bounds on one message's lists, far above what an editor sends, so that an edit costs little.
constexpr size_t kMaxTfPoints = 1024;
constexpr size_t kMaxClipPlanes = 64;
constexpr size_t kMaxRegions = 64;
// describe_histograms: the most voxels one volume's histogram reads, and the most bins.
constexpr double kHistogramSamples = 4.0 * 1024 * 1024;
constexpr int kMaxBins = 4096;
// Names listed in an unknown-object error.
constexpr size_t kMaxListedNames = 24;

// The shortest decimal that reads back as `f`: saved files show 0.95, not 0.949999988079071.
double tidy(float f) {
  const double d = std::strtod(fmt::format("{}", f).c_str(), nullptr);
  return static_cast<float>(d) == f ? d : static_cast<double>(f);
}

Json vec_json(const glm::dvec3& v) {
  return Json::array({v.x, v.y, v.z});
}

glm::dvec3 vec3_of(const Json& j) {
  return {j.at(0).get<double>(), j.at(1).get<double>(), j.at(2).get<double>()};
}

Json camera_json(const Camera& c) {
  return {{"eye", vec_json(c.eye)},
          {"target", vec_json(c.target)},
          {"up", vec_json(c.up)},
          {"fov_deg", c.fov_deg},
          // Read only: the page needs them to project (clip-plane outlines), never sends them.
          {"projection", c.projection == Projection::orthographic ? "orthographic" : "perspective"},
          {"ortho_height", c.ortho_height}};
}

// Points as scene files give them: display colours (the loader decoded them), opacity as is.
Json points_json(const TransferFunction& tf) {
  Json points = Json::array();
  for (const TfPoint& p : tf.points) {
    const glm::vec3 c = linear_to_display(glm::vec3(p.rgba));
    points.push_back({p.value, tidy(c.r), tidy(c.g), tidy(c.b), tidy(p.rgba.a)});
  }
  return points;
}

Json shading_json(const Shading& s) {
  return {{"enabled", s.enabled},
          {"ambient", tidy(s.ambient)},
          {"diffuse", tidy(s.diffuse)},
          {"specular", tidy(s.specular)},
          {"shininess", tidy(s.shininess)}};
}

bool same_shading(const Shading& a, const Shading& b) {
  return a.enabled == b.enabled && a.ambient == b.ambient && a.diffuse == b.diffuse &&
         a.specular == b.specular && a.shininess == b.shininess;
}

bool same_camera(const Camera& a, const Camera& b) {
  return a.eye == b.eye && a.target == b.target && a.up == b.up && a.fov_deg == b.fov_deg &&
         a.ortho_height == b.ortho_height && a.projection == b.projection;
}

// The user's transfer function with its alphas scaled by the opacity: what the document holds
// (the loader makes them 0 when the volume is hidden).
TransferFunction scaled(const TransferFunction& tf, float opacity) {
  TransferFunction out = tf;
  for (TfPoint& p : out.points)
    p.rgba.a = static_cast<float>(static_cast<double>(p.rgba.a) * static_cast<double>(opacity));
  return out;
}

// A number the document holds at `key` of `object`, as the loader reads it into a float.
float document_float(const Json& object, const char* key, float fallback) {
  auto it = object.find(key);
  return it != object.end() && it->is_number() ? static_cast<float>(it->get<double>()) : fallback;
}

// The scene-order index of the object a message names; else an error with the nearest name.
size_t find_object(const Scene& scene, const JsonReader& at) {
  const std::string name = at.string();
  std::vector<std::string> names;
  for (size_t k = 0; k < scene.order.size(); ++k) {
    const std::string& n = object_name(scene, scene.order[k]);
    if (n == name) return k;
    names.push_back(n);
  }
  std::string listed;
  for (size_t i = 0; i < names.size() && i < kMaxListedNames; ++i)
    listed += (i ? ", " : "") + names[i];
  if (names.size() > kMaxListedNames) listed += fmt::format(", ... ({} in all)", names.size());
  at.fail(fmt::format("{} is not an object of the scene{}; they are: {}", at.text(),
                      did_you_mean(name, names), names.empty() ? std::string("(none)") : listed));
}

// The points of a transfer_function edit, checked by the scene loader's own parser.
TransferFunction parse_edit_tf(const JsonReader& at, double unit_distance) {
  if (!at.json().is_array())
    at.fail("expected an array of points [value, r, g, b, a], got " + at.describe());
  if (at.size() > kMaxTfPoints)
    at.fail(fmt::format("{} points; an edit takes at most {}", at.size(), kMaxTfPoints));
  const Json wrapper = {{"points", at.json()}};
  const JsonReader reader(wrapper, at.origin(), at.path());
  scene_json::SceneContext context;  // points need no files
  TransferFunction tf;
  try {
    tf = scene_json::parse_transfer_function(reader, context).transfer_function;
  } catch (const Error& e) {
    // The wrapper's "points" is the message's own transfer_function: name that instead.
    std::string message = e.what();
    const std::string inner = at.path() + ".points";
    if (size_t p = message.find(inner); p != std::string::npos)
      message.replace(p, inner.size(), at.path());
    throw Error(message);
  }
  tf.unit_distance = unit_distance;
  return tf;
}

// The loader's clip_planes check: a point within bounds and a non-zero normal, normalized.
std::vector<ClipPlane> parse_edit_clip_planes(const JsonReader& at) {
  if (!at.json().is_array())
    at.fail("expected an array of {\"point\": [3], \"normal\": [3]}, got " + at.describe());
  if (at.size() > kMaxClipPlanes)
    at.fail(fmt::format("{} clip planes; a volume takes at most {}", at.size(), kMaxClipPlanes));
  return scene_json::parse_clip_planes(at);
}

// A camera's pose as a frame at its target: the columns right, up and backward (eye - target,
// normalized), and the eye's distance.
struct CameraPose {
  glm::dmat3 axes;
  glm::dvec3 target;
  double distance;
};

CameraPose pose_of(const glm::dvec3& eye, const glm::dvec3& target, const glm::dvec3& up) {
  const glm::dvec3 back = glm::normalize(eye - target);
  const glm::dvec3 right = glm::normalize(glm::cross(up, back));
  return {glm::dmat3(right, glm::cross(back, right), back), target, glm::length(eye - target)};
}

// A camera move sent as `from` -> (eye, target, up) applied to `current` instead: the same
// rotation, shift and zoom in the camera's own frame. When another client moved the camera
// since the sender last saw it, both moves then count, and neither undoes the other. Equal to
// the sent camera when `current` is `from`.
void compose_move(Json& current, const CameraPose& from, const CameraPose& to) {
  const CameraPose now =
      pose_of(vec3_of(current["eye"]), vec3_of(current["target"]), vec3_of(current["up"]));
  const glm::dmat3 turn = glm::transpose(from.axes) * to.axes;  // in the sender's frame
  const glm::dvec3 shift = glm::transpose(from.axes) * (to.target - from.target);
  const glm::dmat3 axes = now.axes * turn;
  const glm::dvec3 target = now.target + now.axes * shift;
  const double distance = now.distance * (to.distance / from.distance);
  current["eye"] = vec_json(target + axes[2] * distance);
  current["target"] = vec_json(target);
  current["up"] = vec_json(axes[1]);
}

// Whether the document gives its points in RAS ("space": "RAS"): edits, which come in LPS as
// the page sees the scene, are written back in the document's own space.
bool document_in_ras(const ViewerState& state) {
  const Json& d = state.document.json();
  return d.contains("space") && d["space"] == "RAS";
}

// Negates x and y of a [x, y, z] in place (RAS <-> LPS), when `ras`.
void flip_if_ras(Json& v, bool ras) {
  if (ras && v.is_array() && v.size() == 3)
    v = vec_json(scene_json::to_lps(vec3_of(v), MeshSpace::ras));
}

bool apply_camera(ViewerState& state, const Json& message) {
  const JsonReader r(message, "camera");
  r.check_keys({"type", "seq", "moving", "eye", "target", "up", "fov_deg", "from"});
  // Each field alone first, for a message that names it; then the whole as the loader reads it.
  if (auto v = r.find("eye")) v->vec3(Range::coordinate());
  if (auto v = r.find("target")) v->vec3(Range::coordinate());
  if (auto v = r.find("up")) v->direction();
  if (auto v = r.find("fov_deg")) v->number(Range::open(0.0, 180.0));
  std::optional<std::pair<CameraPose, CameraPose>> move;
  bool keep_fov = false;  // a move that left the fov as it found it leaves another's change
  if (auto from = r.find("from")) {
    // A move: `from` is the camera the sender moved, eye, target and up where it went.
    from->check_keys({"eye", "target", "up", "fov_deg"});
    for (const char* key : {"eye", "target", "up"})
      if (!r.has(key)) r.fail(fmt::format("a move (\"from\") needs \"{}\"", key));
    const Camera a = scene_json::parse_camera(*from);
    const Camera b = scene_json::parse_camera(JsonReader(
        {{"eye", message["eye"]}, {"target", message["target"]}, {"up", message["up"]}}, "camera"));
    const Camera& now = state.scene().camera;
    // Moved from the camera the session has: the sent camera as it is, without rounding.
    if (a.eye != now.eye || a.target != now.target || a.up != now.up)
      move.emplace(pose_of(a.eye, a.target, a.up), pose_of(b.eye, b.target, b.up));
    keep_fov = from->has("fov_deg") && message.contains("fov_deg") &&
               from->json()["fov_deg"] == message["fov_deg"];
  }
  const Camera before = state.scene().camera;
  const bool ras = document_in_ras(state);
  state.document.edit([&](Json& document) {
    Json& camera = document["camera"];  // load_viewer_state wrote one out
    for (const char* key : {"eye", "target", "up"}) flip_if_ras(camera[key], ras);  // to LPS
    if (move)
      compose_move(camera, move->first, move->second);
    else
      for (const char* key : {"eye", "target", "up"})
        if (message.contains(key)) camera[key] = message[key];
    for (const char* key : {"eye", "target", "up"}) flip_if_ras(camera[key], ras);  // back
    if (message.contains("fov_deg") && !keep_fov) camera["fov_deg"] = message["fov_deg"];
  });
  return !same_camera(before, state.scene().camera);
}

// Counts the labels of every label volume whose voxels are new since the last count.
void count_labels(ViewerState& state) {
  const Scene& scene = state.scene();
  state.label_values.resize(scene.volumes.size());
  state.label_data.resize(scene.volumes.size());
  for (size_t i = 0; i < scene.volumes.size(); ++i) {
    const VolumeObject& v = scene.volumes[i];
    if (!v.labels || state.label_data[i] == v.data) continue;
    state.label_values[i] = present_labels(*v.data);
    state.label_data[i] = v.data;
  }
}

// A label edit's rows [{value, visible, opacity, color}] written into the object's
// labels.overrides, each replacing the row of its value (the loader checks them).
void edit_label_overrides(const JsonReader& rows, Json& object) {
  rows.expect_array();
  if (rows.size() > kMaxListedLabels)
    rows.fail(fmt::format("{} labels; an edit holds at most {}", rows.size(), kMaxListedLabels));
  if (!object.contains("labels") || !object["labels"].is_object())
    object["labels"] = Json::object();
  Json& overrides = object["labels"]["overrides"];
  if (!overrides.is_array()) overrides = Json::array();
  for (const JsonReader& row : rows.elements()) {
    row.check_keys({"value", "visible", "opacity", "color"});
    const Json value = row.get("value").json();
    auto same = [&](const Json& o) {
      return o.is_object() && o.contains("value") && o["value"] == value;
    };
    auto it = std::find_if(overrides.begin(), overrides.end(), same);
    Json merged = it != overrides.end() ? *it : Json::object();
    for (const auto& [key, field] : row.json().items()) merged[key] = field;
    if (it != overrides.end())
      *it = std::move(merged);
    else
      overrides.push_back(std::move(merged));
  }
}

// A streamline object's colourings, by the names scene files give them.
constexpr std::array<std::string_view, 6> kColourings = {
    "direction", "streamline_direction", "fixed", "point_value", "streamline_value", "group"};

const char* colouring_name(StreamlineColouring c) {
  return kColourings[static_cast<size_t>(c)].data();
}

Json value_names(const std::vector<StreamlineValues>& values) {
  Json names = Json::array();
  for (const StreamlineValues& v : values) names.push_back(v.name);
  return names;
}

// A `regions` edit: the object's sphere regions, [{"sphere": {"center", "radius"}, "avoid"}],
// in LPS. They replace the document's spheres; its label-map and mesh regions stay (a message
// never names files).
void edit_sphere_regions(const JsonReader& list, Json& object, bool ras) {
  list.expect_array();
  if (list.size() > kMaxRegions)
    list.fail(fmt::format("{} regions; an edit holds at most {}", list.size(), kMaxRegions));
  Json regions = Json::array();
  if (object.contains("regions") && object["regions"].is_array())
    for (const Json& kept : object["regions"])
      if (!kept.is_object() || !kept.contains("sphere")) regions.push_back(kept);
  for (const JsonReader& e : list.elements()) {
    e.check_keys({"sphere", "avoid"});
    const JsonReader sphere = e.get("sphere");
    sphere.check_keys({"center", "radius"});
    Json center = vec_json(sphere.get("center").vec3(Range::coordinate()));
    flip_if_ras(center, ras);
    Json region = {{"sphere",
                    {{"center", std::move(center)},
                     {"radius", sphere.get("radius").number(Range::length())}}}};
    if (auto v = e.find("avoid"); v && v->boolean()) region["avoid"] = true;
    regions.push_back(std::move(region));
  }
  if (regions.empty())
    object.erase("regions");
  else
    object["regions"] = std::move(regions);
}

// A streamline object's edited fields written into its document entry (the loader checks the
// whole again). Colouring by values without a name takes the first values of that kind.
void edit_streamline_object(const JsonReader& r, const StreamlineObject& s, Json& object,
                            float opacity, bool ras) {
  if (r.has("opacity")) object["opacity"] = tidy(opacity);
  std::string colouring = colouring_name(s.colouring);
  if (auto v = r.find("color_by"))
    colouring = v->choice(
        {"direction", "streamline_direction", "fixed", "point_value", "streamline_value", "group"});
  if (r.has("color_by") || r.has("color")) object["color_by"] = colouring;
  if (auto v = r.find("color")) {
    // Written as given: the document holds display colours, the loader decodes them.
    const glm::vec3 c(v->vec3(Range::closed(0.0, 1.0)));
    object["color"] = Json::array({tidy(c.r), tidy(c.g), tidy(c.b)});
  }
  const bool by_value = colouring == "point_value" || colouring == "streamline_value";
  const bool per_point = colouring == "point_value";
  const Streamlines& data = *s.streamlines;
  const auto has = [](const std::vector<StreamlineValues>& values, const std::string& name) {
    return std::any_of(values.begin(), values.end(),
                       [&](const StreamlineValues& x) { return x.name == name; });
  };
  if (auto v = r.find("value")) {
    // Checked here: the loader takes any name, and a wrong one would fail every frame.
    const std::string name = v->string();
    if (name.empty() && !by_value) object.erase("value");  // none (undo gives "" back)
    const bool known = !by_value ? name.empty() || has(data.point_values, name) ||
                                       has(data.streamline_values, name)
                       : per_point ? has(data.point_values, name)
                                   : has(data.streamline_values, name);
    if (!known) {
      const auto& listed = by_value && !per_point ? data.streamline_values : data.point_values;
      std::string names;
      for (const StreamlineValues& x : listed)
        names += (names.empty() ? "'" : ", '") + x.name + "'";
      v->fail(fmt::format("'{}' has no {}values named '{}' (it has {})", s.name,
                          !by_value   ? ""
                          : per_point ? "per-point "
                                      : "per-streamline ",
                          name, names.empty() ? "none" : names));
    }
    if (!name.empty()) object["value"] = name;
  }
  if (by_value && !r.has("value")) {
    const std::vector<StreamlineValues>& values =
        per_point ? data.point_values : data.streamline_values;
    const std::string name = object.contains("value") && object["value"].is_string()
                                 ? object["value"].get<std::string>()
                                 : std::string();
    if (!has(values, name)) {
      if (values.empty())
        (r.has("color_by") ? r.get("color_by") : r)
            .fail(fmt::format("'{}' has no per-{} values", s.name,
                              per_point ? "point" : "streamline"));
      object["value"] = values.front().name;
      object.erase("range");  // another value's range would not fit
    }
  }
  if (auto v = r.find("colormap"))
    object["colormap"] = std::string(colormap_name(scene_json::parse_colormap(*v)));
  if (auto v = r.find("range")) {
    if (v->json().is_null()) {
      object.erase("range");  // the values' own range
    } else {
      const glm::dvec2 range = v->vec2();
      if (!(range.x < range.y)) v->fail("needs [low, high] with low < high");
      object["range"] = v->json();
    }
  }
  if (auto v = r.find("radius")) object["radius"] = v->number(Range::length());
  if (auto v = r.find("stride")) object["stride"] = v->integer(1, 1 << 30);
  if (auto v = r.find("min_length")) object["min_length"] = v->number(Range::closed(0.0, 1e9));
  if (auto v = r.find("regions")) edit_sphere_regions(*v, object, ras);
}

// The edited object as the document holds it: every field checked as the loader checks it (the
// whole document is parsed again after), nothing of the state changed yet.
Json edited_object(const ViewerState& state, const JsonReader& r, size_t k, bool visible,
                   float opacity, TransferFunction& tf) {
  const Scene& scene = state.scene();
  const ObjectRef ref = scene.order[k];
  Json object = state.document.json()["objects"][k];
  if (r.has("visible")) {
    if (visible)
      object.erase("visible");  // the default
    else
      object["visible"] = false;
  }
  if (ref.kind == ObjectKind::volume) {
    const VolumeObject& volume = scene.volumes[static_cast<size_t>(ref.index)];
    if (auto v = r.find("transfer_function")) tf = parse_edit_tf(*v, tf.unit_distance);
    if (auto v = r.find("clip_planes")) {
      parse_edit_clip_planes(*v);
      object["clip_planes"] = v->json();
      for (Json& plane : object["clip_planes"])
        for (const char* key : {"point", "normal"}) flip_if_ras(plane[key], document_in_ras(state));
    }
    if (auto v = r.find("labels")) {
      if (!volume.labels) v->fail(fmt::format("'{}' is not a label volume", volume.name));
      edit_label_overrides(*v, object);
    }
    if (auto v = r.find("window")) {  // the 2-D views' window: [centre, width] or a preset
      const glm::dvec2 w = scene_json::parse_window(*v);
      object["window"] = Json::array({w.x, w.y});
    }
    if (auto v = r.find("slabs")) {  // the 2-D views' thick slabs; none left: the default
      object["slabs"] = scene_json::reading_slabs_json(scene_json::parse_reading_slabs(*v));
      if (object["slabs"].empty()) object.erase("slabs");
    }
    if (auto v = r.find("frame"); v && v->integer(0, volume.frames - 1) != volume.frame) {
      if (!object.contains("source") || !object["source"].is_object() ||
          !object["source"].contains("file"))
        v->fail(fmt::format("'{}' has no file source", volume.name));
      object["source"]["frame"] = v->integer(0, volume.frames - 1);
    }
    if (r.has("transfer_function") || r.has("opacity")) {
      // Explicit points replace a preset or file: keep its shading and unit distance.
      const Json* old_tf =
          object.contains("transfer_function") ? &object["transfer_function"] : nullptr;
      Json written = {{"points", points_json(scaled(tf, opacity))}};
      if (tf.unit_distance != 1.0 || (old_tf && old_tf->contains("unit_distance")))
        written["unit_distance"] = tf.unit_distance;
      object["transfer_function"] = std::move(written);
      if (!object.contains("shading") && !same_shading(volume.shading, Shading{}))
        object["shading"] = shading_json(volume.shading);
    }
  } else if (ref.kind == ObjectKind::streamlines) {
    edit_streamline_object(r, scene.streamlines[static_cast<size_t>(ref.index)], object, opacity,
                           document_in_ras(state));
  } else if (ref.kind == ObjectKind::mesh) {
    if (r.has("opacity")) {
      if (!object.contains("material") || !object["material"].is_object())
        object["material"] = Json::object();
      object["material"]["opacity"] = tidy(opacity);
    }
  } else {
    if (r.has("opacity")) object["opacity"] = tidy(opacity);
    if (auto v = r.find("center")) {
      v->vec3(Range::coordinate());
      object["center"] = v->json();
      flip_if_ras(object["center"], document_in_ras(state));
    }
    if (auto v = r.find("slab")) {  // the plane's thick slab; 0 mm: the plane alone
      const SlabProjection slab = scene_json::parse_slab(*v);
      if (slab.thickness > 0.0)
        object["slab"] = scene_json::slab_json(slab);
      else
        object.erase("slab");
    }
    if (auto v = r.find("window")) {
      const glm::dvec2 w = v->vec2();
      if (!(w.y > 0.0)) v->at(1).fail(fmt::format("window width {} must be > 0", w.y));
      object["window"] = v->json();
    }
  }
  return object;
}

bool apply_object_edit(ViewerState& state, const Json& message) {
  const JsonReader m(message, "edit");
  m.check_keys(
      {"type",   "seq",      "moving",      "object", "visible", "opacity",    "transfer_function",
       "window", "center",   "clip_planes", "frame",  "labels",  "color_by",   "color",
       "value",  "colormap", "range",       "radius", "stride",  "min_length", "regions",
       "slabs",  "slab"});
  const size_t k = find_object(state.scene(), m.get("object"));
  const Json& objects = state.document.json()["objects"];
  if (k >= objects.size() || k >= state.visible.size() || k >= state.opacity.size())
    throw Error("edit: the session's scene document does not match its scene");
  const ObjectRef ref = state.scene().order[k];
  const JsonReader r(message, fmt::format("edit of '{}'", message["object"].get<std::string>()));
  // Every field must fit the object's kind before anything is read.
  const std::pair<const char*, ObjectKind> only[] = {{"transfer_function", ObjectKind::volume},
                                                     {"clip_planes", ObjectKind::volume},
                                                     {"frame", ObjectKind::volume},
                                                     {"labels", ObjectKind::volume},
                                                     {"slabs", ObjectKind::volume},
                                                     {"center", ObjectKind::plane},
                                                     {"slab", ObjectKind::plane},
                                                     {"color_by", ObjectKind::streamlines},
                                                     {"color", ObjectKind::streamlines},
                                                     {"value", ObjectKind::streamlines},
                                                     {"colormap", ObjectKind::streamlines},
                                                     {"range", ObjectKind::streamlines},
                                                     {"radius", ObjectKind::streamlines},
                                                     {"stride", ObjectKind::streamlines},
                                                     {"min_length", ObjectKind::streamlines},
                                                     {"regions", ObjectKind::streamlines}};
  // A connectome is drawn as tubes but has none of a tractogram's fields (its look is its own).
  const bool connectome = ref.kind == ObjectKind::streamlines &&
                          state.scene().streamlines[static_cast<size_t>(ref.index)].connectome;
  if (auto v = r.find("window");
      v && ref.kind != ObjectKind::volume && ref.kind != ObjectKind::plane)
    v->fail(
        fmt::format("applies to volumes (their 2-D views) and planes only, and this object "
                    "is a {}",
                    object_kind_name(ref.kind)));
  for (const auto& [key, kind] : only)
    if (auto v = r.find(key); v && (ref.kind != kind || connectome))
      v->fail(fmt::format("applies to {}s only, and this object is a {}", object_kind_name(kind),
                          connectome ? "connectome" : object_kind_name(ref.kind)));

  bool visible = state.visible[k];
  float opacity = state.opacity[k];
  if (auto v = r.find("visible")) visible = v->boolean();
  if (auto v = r.find("opacity")) opacity = static_cast<float>(v->number(Range::closed(0.0, 1.0)));
  const bool volume = ref.kind == ObjectKind::volume;
  TransferFunction tf =
      volume ? state.transfer_functions[static_cast<size_t>(ref.index)] : TransferFunction{};
  Json object = edited_object(state, r, k, visible, opacity, tf);
  const bool changed = object != objects[k];
  if (changed) {
    try {
      state.document.edit([&](Json& document) { document["objects"][k] = std::move(object); });
    } catch (const Error& e) {
      // The loader names the document's path ("objects[2].center"): say which edit it was.
      throw Error(fmt::format("{}: {}", r.origin(), e.what()));
    }
  }
  if (volume) state.transfer_functions[static_cast<size_t>(ref.index)] = std::move(tf);
  state.visible[k] = visible;
  state.opacity[k] = opacity;
  if (changed) count_labels(state);
  // A volume's window is its 2-D views' alone: the 3-D image stays.
  bool window_only = volume;
  for (const auto& field : message.items())
    if (field.key() != "type" && field.key() != "seq" && field.key() != "moving" &&
        field.key() != "object" && field.key() != "window" && field.key() != "slabs")
      window_only = false;
  return changed && !window_only;
}

// A streamline object's look and selection for the page's controls; its values' names and the
// colour maps are the choices it offers.
void describe_streamlines(const StreamlineObject& s, Json& o) {
  o["name"] = s.name;
  o["color_by"] = colouring_name(s.colouring);
  const glm::vec3 shown = linear_to_display(s.color);  // as the scene file gives it
  o["color"] = Json::array({tidy(shown.r), tidy(shown.g), tidy(shown.b)});
  o["value"] = s.value;
  o["colormap"] = std::string(colormap_name(s.colormap));
  o["range"] = s.range ? Json::array({s.range->x, s.range->y}) : Json(nullptr);
  o["radius"] = s.radius;
  o["stride"] = s.stride;
  o["min_length"] = s.min_length;
  Json regions = Json::array();
  for (const StreamlineRegion& r : s.regions) {
    if (r.shape == StreamlineRegion::Shape::sphere)
      regions.push_back({{"shape", "sphere"},
                         {"center", vec_json(r.center)},
                         {"radius", r.radius},
                         {"avoid", r.avoid}});
    else
      regions.push_back({{"shape", r.shape == StreamlineRegion::Shape::label ? "label" : "mesh"},
                         {"avoid", r.avoid}});
  }
  o["regions"] = std::move(regions);
  const Streamlines* data = s.streamlines.get();
  o["count"] = data ? data->count() : 0;
  o["point_values"] = data ? value_names(data->point_values) : Json::array();
  o["streamline_values"] = data ? value_names(data->streamline_values) : Json::array();
  o["has_groups"] = data && !data->groups.empty();
  Json maps = Json::array();
  for (std::string_view m : kColormapNames) maps.push_back(std::string(m));
  o["colormaps"] = std::move(maps);
}

// Counts of the sampled voxels in `bins` equal bins over their range.
Json histogram(const VolumeData& data, int bins) {
  double lo = std::numeric_limits<double>::infinity(), hi = -lo;
  for_each_sampled_value(data, kHistogramSamples, [&](double s) {
    lo = std::min(lo, s);
    hi = std::max(hi, s);
  });
  std::vector<int64_t> counts(static_cast<size_t>(bins), 0);
  if (!(lo <= hi)) return {{"range", Json::array({0.0, 0.0})}, {"counts", counts}};
  const double scale = hi > lo ? bins / (hi - lo) : 0.0;
  for_each_sampled_value(data, kHistogramSamples, [&](double s) {
    ++counts[static_cast<size_t>(std::min(bins - 1, static_cast<int>((s - lo) * scale)))];
  });
  return {{"range", Json::array({lo, hi})}, {"counts", counts}};
}

}  // namespace

ViewerState load_viewer_state(const std::filesystem::path& file,
                              const std::vector<std::string>& overrides) {
  return viewer_state(SceneDocument::load(file, overrides), file);
}

ViewerState viewer_state(SceneDocument document, std::filesystem::path file) {
  ViewerState state{std::move(document), std::move(file), {}, {}, {}, {}, {}, {}, {}};
  // Edits parse the document again: the framed camera and automatic looks must stay put.
  state.document.write_out_choices();
  const Scene& scene = state.scene();
  state.initial_camera = scene.camera;
  const Json& objects = state.document.json()["objects"];
  state.transfer_functions.resize(scene.volumes.size());
  for (size_t k = 0; k < scene.order.size(); ++k) {
    const Json& object = objects[k];
    const ObjectRef ref = scene.order[k];
    const auto v = object.find("visible");
    const bool visible = v == object.end() || !v->is_boolean() || v->get<bool>();
    state.visible.push_back(visible);
    float opacity = 1.0f;
    if (ref.kind == ObjectKind::mesh && object.contains("material"))
      opacity = document_float(object["material"], "opacity", Material{}.opacity);
    else if (ref.kind == ObjectKind::plane)
      opacity = document_float(object, "opacity", PlaneObject{}.opacity);
    else if (ref.kind == ObjectKind::streamlines)
      opacity = document_float(object, "opacity", StreamlineObject{}.opacity);
    state.opacity.push_back(opacity);
    if (ref.kind != ObjectKind::volume) continue;
    const VolumeObject& volume = scene.volumes[static_cast<size_t>(ref.index)];
    TransferFunction& tf = state.transfer_functions[static_cast<size_t>(ref.index)];
    tf = volume.transfer_function;
    if (visible) continue;
    // Hidden in the file: its alphas are 0 in the scene; the file's own are the user's.
    if (object.contains("transfer_function")) {
      scene_json::SceneContext context;
      context.base_dir = state.document.base_dir();
      tf = scene_json::parse_transfer_function(
               JsonReader(object["transfer_function"], state.document.origin(),
                          fmt::format("objects[{}].transfer_function", k)),
               context)
               .transfer_function;
    } else {
      tf.points = {TfPoint{volume.iso_value, glm::vec4(1.0f)}};  // the loader's iso default
    }
  }
  count_labels(state);
  for (const VolumeObject& v : scene.volumes)
    state.initial_windows.push_back(
        v.data && !v.labels ? initial_display_window(*v.data, v.display_window) : InitialWindow{});
  return state;
}

glm::dvec2 volume_window(const ViewerState& state, size_t i) {
  const VolumeObject& v = state.scene().volumes.at(i);
  if (v.window) return *v.window;
  return i < state.initial_windows.size() ? state.initial_windows[i].window : glm::dvec2(0, 1);
}

bool apply_edit(ViewerState& state, const nlohmann::json& message) {
  if (!message.is_object())
    throw Error(fmt::format("message: expected a JSON object, got {}", message.type_name()));
  const JsonReader r(message, "message");
  const std::string type = r.get("type").string();
  if (type == "camera") return apply_camera(state, message);
  if (type == "edit") return apply_object_edit(state, message);
  r.get("type").fail(fmt::format(
      "{} is not an edit: apply_edit takes \"camera\" and \"edit\" (the server handles the "
      "other types)",
      r.get("type").text()));
}

nlohmann::json describe_state(const ViewerState& state) {
  const Scene& scene = state.scene();
  Json objects = Json::array();
  for (size_t k = 0; k < scene.order.size(); ++k) {
    const ObjectRef ref = scene.order[k];
    const size_t i = static_cast<size_t>(ref.index);
    Json o = {{"kind", object_kind_name(ref.kind)},
              {"visible", k < state.visible.size() ? bool(state.visible[k]) : true},
              {"opacity", k < state.opacity.size() ? tidy(state.opacity[k]) : 1.0}};
    if (ref.kind == ObjectKind::volume) {
      const VolumeObject& v = scene.volumes[i];
      o["name"] = v.name;
      o["transfer_function"] = points_json(
          i < state.transfer_functions.size() ? state.transfer_functions[i] : v.transfer_function);
      Json planes = Json::array();
      for (const ClipPlane& c : v.clip_planes)
        planes.push_back({{"point", vec_json(c.point)}, {"normal", vec_json(c.normal)}});
      o["clip_planes"] = std::move(planes);
      // For the reading views: the grid's world box (voxel centres), the voxel pitch along each
      // world axis (a slice step), and the values' units.
      glm::dvec3 lo(1e300), hi(-1e300);
      for (int c = 0; c < 8; ++c) {
        const glm::dvec3 corner((c & 1) ? v.data->dims.x - 1 : 0, (c & 2) ? v.data->dims.y - 1 : 0,
                                (c & 4) ? v.data->dims.z - 1 : 0);
        const glm::dvec3 w = glm::dvec3(v.index_to_world * glm::dvec4(corner, 1.0));
        lo = glm::min(lo, w);
        hi = glm::max(hi, w);
      }
      const glm::dmat3 to_index = glm::inverse(glm::dmat3(v.index_to_world));
      o["bounds"] = Json::array({vec_json(lo), vec_json(hi)});
      o["pitch"] = vec_json({1.0 / glm::length(to_index[0]), 1.0 / glm::length(to_index[1]),
                             1.0 / glm::length(to_index[2])});
      o["units"] = v.units;
      // The 2-D views' window, and why it is not the header's when the rule refused that.
      const glm::dvec2 window = volume_window(state, i);
      o["window"] = Json::array({window.x, window.y});
      if (!v.window && i < state.initial_windows.size() && !state.initial_windows[i].note.empty())
        o["window_note"] = state.initial_windows[i].note;
      o["slabs"] = scene_json::reading_slabs_json(v.reading_slabs);
      if (v.labels)
        o["labels"] =
            label_list_json(*v.labels, i < state.label_values.size() ? state.label_values[i]
                                                                     : std::vector<int32_t>{});
      if (v.frames > 1) {
        o["frame"] = v.frame;
        o["frames"] = v.frames;
      }
    } else if (ref.kind == ObjectKind::mesh) {
      o["name"] = scene.meshes[i].name;
    } else if (ref.kind == ObjectKind::streamlines && scene.streamlines[i].connectome) {
      o["name"] = scene.streamlines[i].name;  // opacity and visibility only: no tract controls
      o["connectome"] = true;
    } else if (ref.kind == ObjectKind::streamlines) {
      describe_streamlines(scene.streamlines[i], o);
    } else {
      const PlaneObject& p = scene.planes[i];
      o["name"] = p.name;
      o["center"] = vec_json(p.center);
      o["normal"] = vec_json(p.normal);
      o["up"] = vec_json(p.up);
      o["size"] = Json::array({p.size.x, p.size.y});
      o["window"] = Json::array({p.window.x, p.window.y});
      o["slab"] = scene_json::slab_json(p.slab);
      o["volume"] = p.volume >= 0 && static_cast<size_t>(p.volume) < scene.volumes.size()
                        ? Json(scene.volumes[static_cast<size_t>(p.volume)].name)
                        : Json(nullptr);
    }
    objects.push_back(std::move(o));
  }
  // The planes' colour bars, as `render --colorbar` draws them (the page draws the volumes' own
  // from their transfer functions as they are edited): 64 straight RGBA samples from lo to hi,
  // display colours as the page paints them.
  Json bars = Json::array();
  for (const ColourBar& bar : distinct_colour_bars(scene_colour_bars(scene))) {
    if (bar.shown_by.empty()) continue;
    Json colours = Json::array();
    for (int i = 0; i < 64; ++i) {
      const glm::vec4 c = bar.colour(bar.lo + (bar.hi - bar.lo) * i / 63.0);
      const glm::vec3 d = linear_to_display(glm::vec3(c));
      colours.push_back({tidy(d.r), tidy(d.g), tidy(d.b), tidy(c.a)});
    }
    bars.push_back({{"name", bar.name},
                    {"units", bar.units},
                    {"shown_by", bar.shown_by},
                    {"range", {bar.lo, bar.hi}},
                    {"colors", std::move(colours)}});
  }
  return {{"camera", camera_json(scene.camera)},
          {"colour_bars", std::move(bars)},
          {"initial_camera", camera_json(state.initial_camera)},
          {"objects", std::move(objects)},
          {"annotations", annotations_json(state.document.annotations())}};
}

nlohmann::json describe_histograms(const Scene& scene, int bins) {
  if (bins < 1 || bins > kMaxBins)
    throw Error(fmt::format("histograms: {} bins, expected 1 to {}", bins, kMaxBins));
  Json out = Json::object();
  for (const VolumeObject& v : scene.volumes)
    out[v.name] = v.data ? histogram(*v.data, bins) : Json(nullptr);
  return out;
}

nlohmann::json describe_tf_presets() {
  Json out = Json::object();
  scene_json::SceneContext context;  // presets need no files
  for (const std::string& name : volume_preset_names()) {
    const Json source = {{"preset", name}};
    out[name] =
        points_json(scene_json::parse_transfer_function(JsonReader(source, "preset"), context)
                        .transfer_function);
  }
  return out;
}

}  // namespace imx::server
