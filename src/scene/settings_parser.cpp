// Parsers for the scene-wide blocks: camera, image, lights and render settings.
#include <cmath>

#include <fmt/format.h>
#include <glm/glm.hpp>

#include "core/colour.hpp"
#include "scene/scene_parsers.hpp"
#include "scene/world_space.hpp"

namespace imx::scene_json {
namespace {

constexpr int kMaxImageSize = 16384;
constexpr int kMaxCsgStates = 1000000;

bool is_perfect_square(int n) {
  int r = static_cast<int>(std::lround(std::sqrt(static_cast<double>(n))));
  return r * r == n;
}

// Names, or lists of names mixed as one group; the names are checked once the objects are read.
std::vector<std::vector<std::string>> parse_mixing_priority(const JsonReader& r) {
  if (!r.json().is_array())
    r.fail("expected a list of volume names or of lists of names, got " + r.describe());
  std::vector<std::vector<std::string>> groups;
  for (const JsonReader& e : r.elements()) {
    std::vector<std::string> group;
    if (e.json().is_string()) {
      group.push_back(e.string());
    } else if (e.json().is_array()) {
      if (e.size() == 0) e.fail("an empty group (a group lists the volumes mixed together)");
      for (const JsonReader& name : e.elements()) group.push_back(name.string());
    } else {
      e.fail("expected a volume name or a list of names, got " + e.describe());
    }
    groups.push_back(std::move(group));
  }
  return groups;
}

}  // namespace

Camera parse_camera(const JsonReader& r, std::optional<PatientView>* framed_view, MeshSpace space) {
  r.check_keys({"eye", "target", "up", "fov_deg", "projection", "ortho_height", "view"});
  Camera cam;
  if (auto v = r.find("view")) {
    if (framed_view == nullptr) v->fail("a view needs the scene's objects to frame");
    for (const char* placed : {"eye", "target", "up"})
      if (r.has(placed))
        r.get(placed).fail(
            "give either \"view\" (the camera frames the objects) or eye, target "
            "and up, not both");
    *framed_view = find_patient_view(
        v->choice({"anterior", "posterior", "left", "right", "superior", "inferior"}));
  }
  if (auto v = r.find("eye")) cam.eye = to_lps(v->vec3(Range::coordinate()), space);
  if (auto v = r.find("target")) cam.target = to_lps(v->vec3(Range::coordinate()), space);
  if (auto v = r.find("up")) cam.up = to_lps(v->direction(), space);
  if (auto v = r.find("fov_deg")) cam.fov_deg = v->number(Range::open(0.0, 180.0));
  if (auto v = r.find("projection"))
    cam.projection = v->choice({"perspective", "orthographic"}) == "perspective"
                         ? Projection::perspective
                         : Projection::orthographic;
  if (auto v = r.find("ortho_height")) cam.ortho_height = v->number(Range::length());
  glm::dvec3 view = cam.target - cam.eye;
  // Messages give the numbers as the scene wrote them (to_lps undoes itself).
  const glm::dvec3 eye = to_lps(cam.eye, space), up = to_lps(cam.up, space);
  if (glm::length(view) < 1e-9)
    r.fail(fmt::format("eye and target are the same point [{}, {}, {}]", eye.x, eye.y, eye.z));
  if (glm::length(glm::cross(glm::normalize(view), cam.up)) < 1e-6)
    r.fail(fmt::format("up [{}, {}, {}] is parallel to the view direction (target - eye)", up.x,
                       up.y, up.z));
  return cam;
}

ImageSettings parse_image(const JsonReader& r) {
  r.check_keys({"width", "height", "background"});
  ImageSettings image;
  if (auto v = r.find("width")) image.width = v->integer(1, kMaxImageSize);
  if (auto v = r.find("height")) image.height = v->integer(1, kMaxImageSize);
  if (auto v = r.find("background")) {
    if (!v->json().is_array() || (v->json().size() != 3 && v->json().size() != 4))
      v->fail("expected [r, g, b] or [r, g, b, a], got " + v->describe());
    for (size_t i = 0; i < v->json().size(); ++i)
      image.background[static_cast<int>(i)] =
          static_cast<float>(v->at(i).number(Range::closed(0.0, 1.0)));
    if (v->json().size() == 3) image.background.a = 1.0f;
    // A display colour like every other; its alpha stays as given.
    image.background = display_to_linear(image.background);
  }
  return image;
}

std::vector<Light> parse_lights(const JsonReader& r, MeshSpace space) {
  std::vector<Light> lights;
  for (const JsonReader& e : r.elements()) {
    e.check_keys({"type", "direction", "intensity", "color"});
    Light light;
    if (auto v = e.find("type"))
      light.type = v->choice({"headlight", "directional"}) == "headlight" ? LightType::headlight
                                                                          : LightType::directional;
    if (light.type == LightType::directional)
      light.direction = to_lps(e.get("direction").direction(), space);
    else if (auto v = e.find("direction"))
      v->fail("only directional lights have a direction (a headlight shines along the view)");
    if (auto v = e.find("intensity"))
      light.intensity = static_cast<float>(v->number(Range::gain()));
    if (auto v = e.find("color")) light.color = v->color();
    lights.push_back(light);
  }
  return lights;
}

RenderSettings parse_render(const JsonReader& r) {
  r.check_keys({"method", "spp", "step_mm", "reference_step_fraction", "ert_threshold", "layers",
                "rt_layers", "peel_layers", "interpolation", "beta", "skipping", "classification",
                "gradients", "brick_size", "k", "fragment_cap", "thickness", "slab_format",
                "last_volume", "overflow", "sampling", "packets", "peel_rest", "tube_coverage",
                // CSG, and how co-located volumes mix
                "csg_simplify", "csg_presence_threshold", "csg_max_states", "mixing",
                "mixing_priority", "mixing_threshold"});
  RenderSettings s;
  if (auto v = r.find("method")) {
    s.method = v->string();
    if (s.method.empty()) v->fail("the method name is empty");
  }
  if (auto v = r.find("spp")) {
    s.spp = v->integer(1, 1024);
    if (!is_perfect_square(s.spp))
      v->fail(fmt::format("{} is not a perfect square (1, 4, 9, 16, 25, ...)", s.spp));
  }
  if (auto v = r.find("step_mm")) s.step_mm = v->number(Range::length());
  if (auto v = r.find("reference_step_fraction"))
    s.reference_step_fraction = v->number(Range::open_closed(0.0, 1.0));
  if (auto v = r.find("ert_threshold")) s.ert_threshold = v->number(Range::open_closed(0.0, 1.0));
  if (auto v = r.find("layers")) s.layers = v->integer(4, RenderSettings::kMaxLayers);
  if (auto v = r.find("rt_layers")) s.rt_layers = v->integer(1, RenderSettings::kMaxLayers);
  if (auto v = r.find("peel_layers")) s.peel_layers = v->integer(1, 1024);
  if (auto v = r.find("peel_rest")) s.peel_rest = v->choice({"lost", "unsorted"});
  if (auto v = r.find("tube_coverage")) s.tube_coverage = v->choice({"auto", "on", "off"});
  if (auto v = r.find("interpolation")) s.interpolation = v->choice({"ovi", "hvi", "blend"});
  if (auto v = r.find("beta")) s.beta = v->number(Range::closed(0.0, 1.0));
  if (auto v = r.find("skipping")) s.skipping = v->choice({"none", "bricks", "distance"});
  if (auto v = r.find("classification")) s.classification = v->choice({"preintegrated", "post"});
  if (auto v = r.find("gradients")) s.gradients = v->choice({"auto", "on-the-fly", "precomputed"});
  if (auto v = r.find("brick_size")) s.brick_size = v->integer(2, 64);
  if (auto v = r.find("k")) s.k = v->integer(1, 64);
  if (auto v = r.find("fragment_cap")) s.fragment_cap = v->integer(1, 65536);
  if (auto v = r.find("thickness")) s.thickness = parse_thickness(*v);
  if (auto v = r.find("slab_format")) s.slab_format = v->choice({"rgba32f", "rgba8"});
  if (auto v = r.find("last_volume")) s.last_volume = v->string();  // checked with the objects
  if (auto v = r.find("overflow")) s.overflow = v->choice({"greedy", "tail"});
  if (auto v = r.find("sampling")) s.sampling = v->choice({"common", "per-volume"});
  if (auto v = r.find("packets")) s.packets = v->boolean();
  if (auto v = r.find("csg_simplify")) s.csg_simplify = v->choice({"none", "merge", "full"});
  if (auto v = r.find("csg_presence_threshold"))
    s.csg_presence_threshold = v->number(Range::closed(0.0, 1.0));
  if (auto v = r.find("csg_max_states")) s.csg_max_states = v->integer(1, kMaxCsgStates);
  if (auto v = r.find("mixing")) s.mixing = v->choice({"inclusive", "exclusive"});
  if (auto v = r.find("mixing_priority")) s.mixing_priority = parse_mixing_priority(*v);
  if (auto v = r.find("mixing_threshold")) s.mixing_threshold = v->number(Range::closed(0.0, 1.0));
  return s;
}

void check_last_volume(const JsonReader& render, const Scene& scene,
                       const std::map<std::string, std::string>& object_types) {
  std::optional<JsonReader> v = render.find("last_volume");
  if (!v || scene.render.last_volume.empty()) return;
  find_volume(*v, scene.render.last_volume, scene, object_types);
}

void check_mixing_priority(const JsonReader& render, const Scene& scene,
                           const std::map<std::string, std::string>& object_types) {
  std::optional<JsonReader> v = render.find("mixing_priority");
  if (!v) return;
  std::map<std::string, std::string> seen;  // name -> where it is listed
  auto check = [&](const JsonReader& at) {
    const std::string name = at.string();
    find_volume(at, name, scene, object_types);
    if (auto [it, fresh] = seen.emplace(name, at.path()); !fresh)
      at.fail(fmt::format("'{}' is already at {} (a volume has one priority)", name, it->second));
  };
  for (const JsonReader& e : v->elements()) {
    if (e.json().is_array())
      for (const JsonReader& name : e.elements()) check(name);
    else
      check(e);
  }
}

}  // namespace imx::scene_json
