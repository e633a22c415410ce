#include "movie/slice_sweep.hpp"

#include <algorithm>
#include <cmath>

#include <fmt/format.h>
#include <glm/geometric.hpp>

#include "core/math.hpp"
#include "intermix/error.hpp"
#include "scene/reading_planes.hpp"

namespace imx {

namespace {

constexpr glm::dvec3 kNormals[] = {{0, 0, 1}, {0, 1, 0}, {1, 0, 0}};  // LPS, SweepAxis's order

// The first visible plane facing along `normal` (within about 2.5 degrees) that shows a volume.
int find_plane(const Scene& scene, const glm::dvec3& normal) {
  for (size_t i = 0; i < scene.planes.size(); ++i) {
    const PlaneObject& p = scene.planes[i];
    if (p.volume >= 0 && p.opacity > 0.0f && std::abs(glm::dot(p.normal, normal)) > 0.999)
      return static_cast<int>(i);
  }
  return -1;
}

// Adds the reading plane of `axis` through the first volume, shown, and hides that volume.
std::string add_plane(SceneDocument& document, SweepAxis axis) {
  nlohmann::json plane = reading_planes(document.scene())[static_cast<size_t>(axis)];
  plane.erase("visible");
  const std::string volume = plane["volume"];
  if (document.json().value("space", "LPS") == "RAS")  // the reading planes are LPS
    for (const char* key : {"center", "normal", "up"})
      for (int c = 0; c < 2; ++c) plane[key][c] = -plane[key][c].get<double>();
  document.edit([&](nlohmann::json& json) {
    for (nlohmann::json& object : json["objects"])
      if (object.value("name", "") == volume) object["visible"] = false;
    json["objects"].push_back(plane);
  });
  return fmt::format(
      "--sweep {}: added plane '{}' through volume '{}' and hid the volume's own rendering (a "
      "visible {} plane in a scene file sweeps instead, with the scene as it is)",
      sweep_axis_names()[static_cast<size_t>(axis)], plane["name"].get<std::string>(), volume,
      sweep_axis_names()[static_cast<size_t>(axis)]);
}

}  // namespace

const std::vector<std::string>& sweep_axis_names() {
  static const std::vector<std::string> names = {"axial", "coronal", "sagittal"};
  return names;
}

std::optional<SweepAxis> find_sweep_axis(std::string_view name) {
  const std::vector<std::string>& names = sweep_axis_names();
  for (size_t i = 0; i < names.size(); ++i)
    if (names[i] == name) return static_cast<SweepAxis>(i);
  return std::nullopt;
}

const char* sweep_view(SweepAxis axis) {
  switch (axis) {
    case SweepAxis::axial:
      return "inferior";
    case SweepAxis::coronal:
      return "anterior";
    case SweepAxis::sagittal:
      return "left";
  }
  return "anterior";
}

SliceSweep plan_slice_sweep(SceneDocument& document, SweepAxis axis, int frames) {
  const std::string& name = sweep_axis_names()[static_cast<size_t>(axis)];
  if (document.scene().volumes.empty())
    throw Error(fmt::format("{}: --sweep {} needs a volume to sweep through; the scene has none",
                            document.origin(), name));
  const glm::dvec3 normal = kNormals[static_cast<size_t>(axis)];
  SliceSweep sweep;
  sweep.plane = find_plane(document.scene(), normal);
  if (sweep.plane < 0) {
    sweep.notes.push_back(add_plane(document, axis));
    sweep.plane = find_plane(document.scene(), normal);
  }
  const Scene& scene = document.scene();
  const PlaneObject& plane = scene.planes[static_cast<size_t>(sweep.plane)];
  const VolumeObject& volume = scene.volumes[static_cast<size_t>(plane.volume)];
  // The voxel centres' extent along the plane's normal, and the step between voxel slices: the
  // index axis most along the normal.
  const glm::ivec3 dims = volume.data->dims;
  double lo = 1e300, hi = -1e300;
  for (int c = 0; c < 8; ++c) {
    const glm::dvec3 index((c & 1) ? dims.x - 1 : 0, (c & 2) ? dims.y - 1 : 0,
                           (c & 4) ? dims.z - 1 : 0);
    const double s = glm::dot(transform_point(volume.index_to_world, index), plane.normal);
    lo = std::min(lo, s);
    hi = std::max(hi, s);
  }
  if (frames <= 0) {
    int slices = 1;
    double best = 0.0;
    for (int a = 0; a < 3; ++a) {
      const glm::dvec3 column(volume.index_to_world[a]);
      const double along = std::abs(glm::dot(column, plane.normal)) / glm::length(column);
      if (along > best) {
        best = along;
        slices = dims[a];
      }
    }
    frames = std::max(1, slices);
  }
  const double here = glm::dot(plane.center, plane.normal);
  for (int k = 0; k < frames; ++k) {
    const double s = frames == 1 ? 0.5 * (lo + hi) : lo + (hi - lo) * k / (frames - 1);
    sweep.centres.push_back(plane.center + (s - here) * plane.normal);
  }
  return sweep;
}

}  // namespace imx
