#include "dist/brick_levels.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include <glm/glm.hpp>

#include "io/voxels/raw_voxels.hpp"
#include "io/zarr/ome_zarr_reader.hpp"
#include "volume/level_of_detail.hpp"

namespace imx {
namespace {

// The OME-Zarr folder a volume object's source names, or empty.
std::filesystem::path zarr_source(const nlohmann::json& object,
                                  const std::filesystem::path& base_dir) {
  const auto source = object.find("source");
  if (source == object.end()) return {};
  const nlohmann::json* file = &*source;
  if (source->is_object()) {
    const auto f = source->find("file");
    if (f == source->end()) return {};
    file = &*f;
  }
  if (!file->is_string()) return {};
  std::filesystem::path path(file->get<std::string>());
  if (path.is_relative() && !base_dir.empty()) path = base_dir / path;
  return detail::is_zarr_folder(path) ? path : std::filesystem::path();
}

// The whole grid's placement of a volume object loaded by region.
glm::dmat4 whole_placement(const VolumeObject& v) {
  return box_index_to_world(v.index_to_world, -v.region.lo);
}

}  // namespace

std::vector<PyramidLevels> scene_pyramids(const SceneDocument& outline) {
  std::vector<PyramidLevels> pyramids;
  const nlohmann::json& objects = outline.json().at("objects");
  const Scene& scene = outline.scene();
  const auto one_voxel = [](const std::string&, const VolumeHeader&) {
    return VoxelBox{glm::ivec3(0), glm::ivec3(1)};
  };
  for (size_t k = 0; k < scene.order.size(); ++k) {
    if (scene.order[k].kind != ObjectKind::volume) continue;
    const std::filesystem::path path = zarr_source(objects.at(k), outline.base_dir());
    if (path.empty()) continue;
    const nlohmann::json& source = objects[k]["source"];
    // A level the document names is the finest a render of it reads.
    const nlohmann::json asked =
        source.is_object() ? source.value("level", nlohmann::json(0)) : nlohmann::json(0);
    const int first = asked.is_number_integer() ? asked.get<int>() : 0;
    const int count = detail::read_ome_zarr_level_count(path);
    if (count - first < 2) continue;
    PyramidLevels p;
    p.object = k;
    p.first_level = first;
    for (int level = first; level < count; ++level) {
      nlohmann::json json = outline.json();
      nlohmann::json& src = json["objects"][k]["source"];
      if (!src.is_object()) src = nlohmann::json{{"file", src}};
      src["level"] = level;
      const SceneDocument at(std::move(json), outline.origin(), outline.base_dir(), {}, {},
                             one_voxel);
      const VolumeObject& v = at.scene().volumes[static_cast<size_t>(at.scene().order[k].index)];
      p.dims.push_back(v.source_dims);
      p.index_to_world.push_back(whole_placement(v));
    }
    pyramids.push_back(std::move(p));
  }
  return pyramids;
}

int level_fitting(const PyramidLevels& pyramid, double footprint) {
  int fitting = 0;
  for (size_t level = 1; level < pyramid.index_to_world.size(); ++level) {
    if (longest_voxel_edge(pyramid.index_to_world[level]) <= footprint)
      fitting = static_cast<int>(level);
  }
  return fitting;
}

void world_bounds(const PyramidLevels& pyramid, const VoxelBox& box, glm::dvec3& lo,
                  glm::dvec3& hi) {
  world_box(pyramid.index_to_world[0], box.lo, box.hi, lo, hi);
}

VoxelBox box_at_level(const PyramidLevels& pyramid, int level, const VoxelBox& box) {
  const size_t l = static_cast<size_t>(level);
  const glm::dmat4 to_level = glm::inverse(pyramid.index_to_world[l]) * pyramid.index_to_world[0];
  glm::dvec3 lo(std::numeric_limits<double>::infinity()), hi = -lo;
  for (int c = 0; c < 8; ++c) {
    const glm::dvec4 index((c & 1) ? box.hi.x - 1 : box.lo.x, (c & 2) ? box.hi.y - 1 : box.lo.y,
                           (c & 4) ? box.hi.z - 1 : box.lo.z, 1.0);
    const glm::dvec3 at(to_level * index);
    lo = glm::min(lo, at);
    hi = glm::max(hi, at);
  }
  const glm::ivec3 dims = pyramid.dims[l];
  VoxelBox out;
  for (int a = 0; a < 3; ++a) {
    // The cells holding the corners, and one voxel beyond them for the neighbour's side.
    out.lo[a] = std::clamp(static_cast<int>(std::floor(lo[a])) - 1, 0, dims[a] - 1);
    out.hi[a] = std::clamp(static_cast<int>(std::ceil(hi[a])) + 2, out.lo[a] + 1, dims[a]);
  }
  return out;
}

}  // namespace imx
