#include "dist/partition.hpp"

#include <algorithm>
#include <numeric>
#include <set>

#include <fmt/format.h>
#include <glm/glm.hpp>

#include "intermix/error.hpp"

namespace imx {

namespace {

// Rough costs in voxel-sample units: a mesh costs its triangles plus a fixed share for the
// fragments it shades; a plane a fixed share. Dealing is only as good as these guesses.
constexpr double kCostPerTriangle = 64.0;
constexpr double kCostPerSurface = double(1 << 18);

// A piece dealt whole: a volume with the planes that sample it, a mesh, or a free plane.
struct Unit {
  std::vector<size_t> objects;  // Scene::order indices
  double cost = 0.0;
};

double voxels_of(const VolumeObject& v) {
  return static_cast<double>(v.source_dims.x) * v.source_dims.y * v.source_dims.z;
}

// Per volume, the planes (order indices) that sample it. A hidden plane (opacity 0, as the
// viewer's reading planes are in 3-D) samples nothing, so it does not keep its volume whole.
std::vector<std::vector<size_t>> planes_by_volume(const Scene& scene) {
  std::vector<std::vector<size_t>> by(scene.volumes.size());
  for (size_t k = 0; k < scene.order.size(); ++k)
    if (scene.order[k].kind == ObjectKind::plane) {
      const PlaneObject& plane = scene.planes[scene.order[k].index];
      if (plane.volume >= 0 && plane.opacity > 0.0f)
        by[static_cast<size_t>(plane.volume)].push_back(k);
    }
  return by;
}

// Largest first onto the least loaded rank (LPT); ties go to the lowest rank, so every rank
// plans the same.
void deal(std::vector<Unit> units, std::vector<RankPart>& ranks) {
  std::stable_sort(units.begin(), units.end(),
                   [](const Unit& a, const Unit& b) { return a.cost > b.cost; });
  for (Unit& u : units) {
    auto least =
        std::min_element(ranks.begin(), ranks.end(),
                         [](const RankPart& a, const RankPart& b) { return a.cost < b.cost; });
    least->objects.insert(least->objects.end(), u.objects.begin(), u.objects.end());
    least->cost += u.cost;
  }
  for (RankPart& r : ranks) std::sort(r.objects.begin(), r.objects.end());  // scene order
}

// Cuts the grid points lo..hi into `count` pieces by halving the longest world extent.
void split(glm::ivec3 lo, glm::ivec3 hi, int count, const glm::dvec3& pitch,
           std::vector<std::pair<glm::ivec3, glm::ivec3>>& out) {
  int axis = -1;
  double longest = 0.0;
  for (int a = 0; a < 3; ++a) {
    double extent = (hi[a] - lo[a]) * pitch[a];
    if (hi[a] - lo[a] >= 2 && extent > longest) {
      longest = extent;
      axis = a;
    }
  }
  if (count == 1 || axis < 0) {  // too thin to cut further: the rest of the ranks get none
    out.emplace_back(lo, hi);
    return;
  }
  const int left = count / 2;
  int cut = lo[axis] +
            static_cast<int>(std::lround(static_cast<double>(hi[axis] - lo[axis]) * left / count));
  cut = std::clamp(cut, lo[axis] + 1, hi[axis] - 1);
  glm::ivec3 left_hi = hi, right_lo = lo;
  left_hi[axis] = cut;
  right_lo[axis] = cut;
  split(lo, left_hi, left, pitch, out);
  split(right_lo, hi, count - left, pitch, out);
}

std::vector<Unit> units_of(const Scene& scene, const std::set<size_t>& bricked_volumes) {
  const std::vector<std::vector<size_t>> sampled_by = planes_by_volume(scene);
  std::vector<Unit> units;
  for (size_t k = 0; k < scene.order.size(); ++k) {
    const ObjectRef& ref = scene.order[k];
    Unit u;
    if (ref.kind == ObjectKind::volume) {
      if (bricked_volumes.count(static_cast<size_t>(ref.index))) continue;
      const VolumeObject& v = scene.volumes[ref.index];
      u.objects.push_back(k);
      u.cost = voxels_of(v);
      for (size_t p : sampled_by[static_cast<size_t>(ref.index)]) {
        u.objects.push_back(p);
        u.cost += kCostPerSurface;
      }
    } else if (ref.kind == ObjectKind::mesh) {
      u.objects.push_back(k);
      u.cost =
          kCostPerSurface +
          kCostPerTriangle * static_cast<double>(scene.meshes[ref.index].mesh->triangles.size());
    } else if (ref.kind == ObjectKind::streamlines) {
      u.objects.push_back(k);
      u.cost = kCostPerSurface +
               kCostPerTriangle *
                   static_cast<double>(scene.streamlines[ref.index].streamlines->points.size());
    } else {
      if (scene.planes[ref.index].volume >= 0) continue;  // goes with its volume
      u.objects.push_back(k);
      u.cost = kCostPerSurface;
    }
    units.push_back(std::move(u));
  }
  return units;
}

Partition deal_objects(const Scene& scene, int ranks) {
  Partition p;
  p.mode = PartitionMode::objects;
  p.ranks.resize(static_cast<size_t>(ranks));
  deal(units_of(scene, {}), p.ranks);
  return p;
}

Partition cut_bricks(const Scene& scene, int ranks) {
  Partition p;
  p.mode = PartitionMode::bricks;
  p.ranks.resize(static_cast<size_t>(ranks));
  const std::vector<std::vector<size_t>> sampled_by = planes_by_volume(scene);
  std::set<size_t> bricked;
  for (size_t v = 0; v < scene.volumes.size(); ++v) {
    const VolumeObject& vol = scene.volumes[v];
    if (voxels_of(vol) < static_cast<double>(kMinBrickedVoxels) || !sampled_by[v].empty()) continue;
    // The whole volume's placement: the object's, moved back from the part it holds.
    glm::dmat4 whole = box_index_to_world(vol.index_to_world, -vol.region.lo);
    glm::dvec3 pitch(glm::length(glm::dvec3(whole[0])), glm::length(glm::dvec3(whole[1])),
                     glm::length(glm::dvec3(whole[2])));
    std::vector<std::pair<glm::ivec3, glm::ivec3>> pieces;
    split(glm::ivec3(0), vol.source_dims - 1, ranks, pitch, pieces);
    for (size_t r = 0; r < pieces.size(); ++r) {
      VolumeBrick b = make_brick(pieces[r].first, pieces[r].second, vol.source_dims, whole);
      p.ranks[r].cost += static_cast<double>(b.read.count());
      p.ranks[r].bricks.emplace(vol.name, std::move(b));
    }
    bricked.insert(v);
  }
  deal(units_of(scene, bricked), p.ranks);
  return p;
}

}  // namespace

PartitionMode parse_partition_mode(const std::string& name) {
  if (name == "objects") return PartitionMode::objects;
  if (name == "bricks") return PartitionMode::bricks;
  if (name == "auto") return PartitionMode::automatic;
  throw Error(fmt::format("--partition is '{}', expected objects, bricks or auto", name));
}

const char* partition_mode_name(PartitionMode mode) {
  switch (mode) {
    case PartitionMode::objects:
      return "objects";
    case PartitionMode::bricks:
      return "bricks";
    case PartitionMode::automatic:
      return "auto";
  }
  return "unknown";
}

VolumeBrick make_brick(glm::ivec3 lo, glm::ivec3 hi, glm::ivec3 dims,
                       const glm::dmat4& index_to_world) {
  VolumeBrick b;
  b.lo = lo;
  b.hi = hi;
  const glm::dmat3 to_index = glm::inverse(glm::dmat3(index_to_world));
  for (int a = 0; a < 3; ++a) {
    b.read.lo[a] = lo[a] > 0 ? lo[a] - 1 : 0;
    b.read.hi[a] = hi[a] < dims[a] - 1 ? hi[a] + 2 : dims[a];
    // The direction in which index a grows: row a of the inverse of the linear part.
    const glm::dvec3 normal =
        glm::normalize(glm::dvec3(to_index[0][a], to_index[1][a], to_index[2][a]));
    auto plane_at = [&](int index, double sign) {
      glm::dvec4 at(0.0, 0.0, 0.0, 1.0);
      at[a] = index;
      b.bounds.push_back({glm::dvec3(index_to_world * at), sign * normal});
    };
    if (lo[a] > 0) plane_at(lo[a], 1.0);
    if (hi[a] < dims[a] - 1) plane_at(hi[a], -1.0);
  }
  return b;
}

Partition plan_partition(const Scene& scene, int ranks, PartitionMode mode) {
  if (ranks < 1) throw Error(fmt::format("distributed: {} processes, need at least 1", ranks));
  if (scene.csg)
    throw Error(
        "distributed: a scene with a csg block is not distributed yet; render it in one process");
  if (mode == PartitionMode::objects) return deal_objects(scene, ranks);
  if (mode == PartitionMode::bricks) return cut_bricks(scene, ranks);
  Partition objects = deal_objects(scene, ranks);
  double total = 0.0, most = 0.0;
  for (const RankPart& r : objects.ranks) {
    total += r.cost;
    most = std::max(most, r.cost);
  }
  if (most <= 1.25 * total / ranks) return objects;
  return cut_bricks(scene, ranks);
}

std::string Partition::describe(const Scene& scene, int rank) const {
  const RankPart& part = ranks.at(static_cast<size_t>(rank));
  std::vector<std::string> items;
  for (const auto& [name, b] : part.bricks)
    items.push_back(fmt::format("{}[{}..{}, {}..{}, {}..{}]", name, b.lo.x, b.hi.x, b.lo.y, b.hi.y,
                                b.lo.z, b.hi.z));
  for (size_t k : part.objects) {
    const ObjectRef& ref = scene.order[k];
    items.push_back(object_name(scene, ref));
  }
  std::string list;
  for (const std::string& s : items) list += (list.empty() ? "" : ", ") + s;
  return fmt::format("rank {}: {}", rank, list.empty() ? "nothing" : list);
}

}  // namespace imx
