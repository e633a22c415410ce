#include "server/annotation_messages.hpp"

#include <chrono>
#include <cmath>
#include <limits>
#include <map>

#include <fmt/format.h>

#include "core/camera_model.hpp"
#include "intermix/error.hpp"
#include "measure/measurement.hpp"
#include "probes/first_hit_depth.hpp"
#include "scene/scene_parsers.hpp"

namespace imx::server {
namespace {

using Json = nlohmann::json;
using scene_json::JsonReader;
using scene_json::Range;

// Every object's name and kind, for the parser's "'x' is a mesh, not a volume".
std::map<std::string, std::string> object_types(const Scene& scene) {
  std::map<std::string, std::string> types;
  for (const ObjectRef& ref : scene.order)
    types[object_name(scene, ref)] = object_kind_name(ref.kind);
  return types;
}

// The message's list, parsed as the scene parser parses the document's (the same checks and
// messages, its paths under the message's name).
std::vector<Annotation> parse_list(const ViewerState& state, const JsonReader& r) {
  return scene_json::parse_annotations(r.get("annotations"), state.scene(),
                                       object_types(state.scene()), MeshSpace::lps);
}

Json annotation_json(const Annotation& a, bool ras) {
  Json points = Json::array();
  for (const glm::dvec3& p : a.points)
    points.push_back(ras ? Json::array({-p.x, -p.y, p.z}) : Json::array({p.x, p.y, p.z}));
  Json j = {{"kind", annotation_kind_name(a.kind)}, {"points", std::move(points)}};
  if (!a.volume.empty()) j["volume"] = a.volume;
  if (!a.label.empty()) j["label"] = a.label;
  return j;
}

}  // namespace

Json answer_pick(const ViewerState& state, const Json& message) {
  const JsonReader r(message, "pick");
  r.check_keys({"type", "seq", "x", "y", "width", "height"});
  const int width = r.get("width").integer(1, 16384), height = r.get("height").integer(1, 16384);
  const double x = r.get("x").number(Range::closed(0.0, width));
  const double y = r.get("y").number(Range::closed(0.0, height));
  const Scene& scene = state.scene();
  const CameraModel model(scene.camera, width, height);
  const Ray ray = model.ray(x, y);
  // The ray as the central one of a 1x1 image: the same origin and direction, a sliver of view.
  Scene one = scene;
  one.image.width = one.image.height = 1;
  one.camera.eye = glm::dvec3(ray.origin);
  one.camera.target = glm::dvec3(ray.origin) + 100.0 * glm::dvec3(ray.dir);
  one.camera.up = model.up();
  one.camera.fov_deg = 1e-4;
  one.camera.ortho_height = 1e-4;
  double nearest = std::numeric_limits<double>::infinity();
  std::string hit;
  for (size_t k = 0; k < scene.order.size(); ++k) {
    if (k < state.visible.size() && !state.visible[k]) continue;
    const std::string& name = object_name(scene, scene.order[k]);
    const double t = first_hit_depth(one, name, 0.5f, 1).at(0, 0).r;
    if (t < nearest) {
      nearest = t;
      hit = name;
    }
  }
  Json out = {{"type", "pick"}, {"point", nullptr}, {"object", nullptr}};
  if (std::isfinite(nearest)) {
    const glm::dvec3 p = glm::dvec3(ray.origin) + nearest * glm::dvec3(ray.dir);
    out["point"] = Json::array({p.x, p.y, p.z});
    out["object"] = hit;
  }
  if (message.contains("seq")) out["seq"] = message["seq"];
  return out;
}

Json annotations_json(const std::vector<Annotation>& annotations) {
  Json list = Json::array();
  for (const Annotation& a : annotations) list.push_back(annotation_json(a, false));
  return list;
}

bool apply_annotations(ViewerState& state, const Json& message) {
  const JsonReader r(message, "annotations");
  r.check_keys({"type", "seq", "moving", "annotations"});
  const std::vector<Annotation> parsed = parse_list(state, r);
  // Written in the document's own space; the loader reads them back into the same LPS points.
  const Json& document = state.document.json();
  const bool ras = document.contains("space") && document["space"] == "RAS";
  Json list = Json::array();
  for (const Annotation& a : parsed) list.push_back(annotation_json(a, ras));
  const Json before = document.contains("annotations") ? document["annotations"] : Json::array();
  if (list == before) return false;
  try {
    state.document.edit([&](Json& d) {
      if (list.empty())
        d.erase("annotations");
      else
        d["annotations"] = std::move(list);
    });
  } catch (const Error& e) {
    throw Error(fmt::format("annotations: {}", e.what()));
  }
  return true;
}

Json answer_measure(const ViewerState& state, const Json& message) {
  const auto t0 = std::chrono::steady_clock::now();
  const JsonReader r(message, "measure");
  r.check_keys({"type", "seq", "annotations"});
  const JsonReader list = r.get("annotations");
  list.expect_array();
  if (list.size() > kMaxMeasuredAnnotations)
    list.fail(fmt::format("{} annotations, more than the {} one measure message may ask for",
                          list.size(), kMaxMeasuredAnnotations));
  Json measurements = Json::array();
  for (const Annotation& a : parse_list(state, r))
    measurements.push_back(measurement_json(a, measure(a, state.scene())));
  Json out = {{"type", "measure"}, {"measurements", std::move(measurements)}};
  if (message.contains("seq")) out["seq"] = message["seq"];
  out["ms"] =
      std::round(
          std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count() *
          100) /
      100;
  return out;
}

}  // namespace imx::server
