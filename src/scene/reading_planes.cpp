#include "scene/reading_planes.hpp"

#include <set>
#include <string>

#include <fmt/format.h>

#include "core/math.hpp"
#include "volume/display_window.hpp"

namespace imx {
namespace {

using Json = nlohmann::json;

// Short decimal numbers in the document, not 17-digit doubles.
double tidy(double v) {
  return std::stod(fmt::format("{:.6g}", v));
}

Json vec(const glm::dvec3& v) {
  return Json::array({tidy(v.x), tidy(v.y), tidy(v.z)});
}

std::string free_name(const std::string& base, const std::set<std::string>& taken) {
  std::string name = base;
  for (int n = 2; taken.count(name); ++n) name = fmt::format("{}-{}", base, n);
  return name;
}

}  // namespace

glm::dvec2 reading_window(const VolumeObject& volume) {
  if (volume.window) return *volume.window;
  if (!volume.data) return {0.0, 1.0};
  return initial_display_window(*volume.data, volume.display_window).window;
}

nlohmann::json reading_planes(const Scene& scene) {
  Json planes = Json::array();
  if (scene.volumes.empty() || !scene.volumes.front().data) return planes;
  const VolumeObject& v = scene.volumes.front();
  const glm::ivec3 dims = v.data->dims;
  glm::dvec3 lo(1e300), hi(-1e300);
  for (int c = 0; c < 8; ++c) {
    const glm::dvec3 index((c & 1) ? dims.x - 1 : 0, (c & 2) ? dims.y - 1 : 0,
                           (c & 4) ? dims.z - 1 : 0);
    const glm::dvec3 w = transform_point(v.index_to_world, index);
    lo = glm::min(lo, w);
    hi = glm::max(hi, w);
  }
  const glm::dvec3 centre = 0.5 * (lo + hi), extent = glm::max(hi - lo, glm::dvec3(1.0));
  const glm::dvec2 window = reading_window(v);
  std::set<std::string> taken;
  for (const VolumeObject& o : scene.volumes) taken.insert(o.name);
  for (const MeshObject& o : scene.meshes) taken.insert(o.name);
  for (const PlaneObject& o : scene.planes) taken.insert(o.name);
  struct Axis {
    const char* name;
    glm::dvec3 normal, up;
    glm::dvec2 size;
  };
  const Axis axes[] = {
      {"axial", {0, 0, 1}, {0, -1, 0}, {extent.x, extent.y}},
      {"coronal", {0, 1, 0}, {0, 0, 1}, {extent.x, extent.z}},
      {"sagittal", {1, 0, 0}, {0, 0, 1}, {extent.y, extent.z}},
  };
  for (const Axis& a : axes) {
    const std::string name = free_name(a.name, taken);
    taken.insert(name);
    planes.push_back({{"name", name},
                      {"type", "plane"},
                      {"visible", false},
                      {"volume", v.name},
                      {"center", vec(centre)},
                      {"normal", vec(a.normal)},
                      {"up", vec(a.up)},
                      {"size", Json::array({tidy(a.size.x), tidy(a.size.y)})},
                      {"window", Json::array({tidy(window.x), tidy(window.y)})}});
  }
  return planes;
}

}  // namespace imx
