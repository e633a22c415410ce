#include "dist/rank_scene.hpp"

#include <algorithm>
#include <set>

#include <glm/glm.hpp>

namespace imx {

namespace {

// The names of the volume objects rank `rank` renders whole.
std::set<std::string> whole_volumes(const Partition& partition, int rank, const Scene& scene) {
  std::set<std::string> names;
  for (size_t k : partition.ranks.at(static_cast<size_t>(rank)).objects)
    if (scene.order[k].kind == ObjectKind::volume)
      names.insert(scene.volumes[scene.order[k].index].name);
  return names;
}

// The smallest voxel pitch over the scene's volumes, as a frame computes it (in float), 0 with
// no volume. A part holds the whole's spacing, so every rank finds the same.
double smallest_pitch(const Scene& scene) {
  double pitch = 0.0;
  for (const VolumeObject& v : scene.volumes) {
    glm::dmat3 linear(v.index_to_world);
    double p = static_cast<double>(static_cast<float>(
        std::min({glm::length(linear[0]), glm::length(linear[1]), glm::length(linear[2])})));
    pitch = pitch == 0.0 ? p : std::min(pitch, p);
  }
  return pitch;
}

}  // namespace

VolumeRegionChooser rank_regions(const Partition& partition, int rank, const Scene& outline) {
  const RankPart& part = partition.ranks.at(static_cast<size_t>(rank));
  std::map<std::string, VoxelBox> bricks;
  for (const auto& [name, brick] : part.bricks) bricks.emplace(name, brick.read);
  std::set<std::string> whole = whole_volumes(partition, rank, outline);
  return [bricks, whole](const std::string& object, const VolumeHeader& header) {
    if (auto it = bricks.find(object); it != bricks.end()) return it->second;
    if (whole.count(object)) return VoxelBox::whole(header.dims);
    return VoxelBox{glm::ivec3(0), glm::ivec3(1)};
  };
}

Scene rank_scene(const Scene& loaded, const Partition& partition, int rank) {
  const RankPart& part = partition.ranks.at(static_cast<size_t>(rank));
  const std::set<size_t> mine(part.objects.begin(), part.objects.end());
  const double pitch = smallest_pitch(loaded);

  // Which objects go in: those rendered here, the bricks, and the clip meshes of their volumes.
  std::vector<bool> keep(loaded.order.size(), false), hidden(loaded.order.size(), false);
  std::vector<int> order_of_mesh(loaded.meshes.size(), -1);
  for (size_t k = 0; k < loaded.order.size(); ++k)
    if (loaded.order[k].kind == ObjectKind::mesh) order_of_mesh[loaded.order[k].index] = int(k);
  for (size_t k = 0; k < loaded.order.size(); ++k) {
    const ObjectRef& ref = loaded.order[k];
    bool here = mine.count(k) > 0;
    if (ref.kind == ObjectKind::volume)
      here = here || part.bricks.count(loaded.volumes[ref.index].name) > 0;
    if (!here) continue;
    keep[k] = true;
    if (ref.kind == ObjectKind::volume)
      for (const ClipMesh& c : loaded.volumes[ref.index].clip_meshes) {
        size_t m = static_cast<size_t>(order_of_mesh.at(static_cast<size_t>(c.mesh)));
        if (!keep[m] && !mine.count(m)) hidden[m] = true;
      }
    if (ref.kind == ObjectKind::streamlines)
      for (const ClipMesh& c : loaded.streamlines[ref.index].clip_meshes) {
        size_t m = static_cast<size_t>(order_of_mesh.at(static_cast<size_t>(c.mesh)));
        if (!keep[m] && !mine.count(m)) hidden[m] = true;
      }
  }

  Scene sub;
  sub.camera = loaded.camera;
  sub.image = loaded.image;
  sub.lights = loaded.lights;
  sub.render = loaded.render;
  sub.file = loaded.file;
  sub.render.pitch_mm = pitch;
  const bool auto_thickness = pitch > 0.0 && !loaded.render.thickness;
  std::vector<int> volume_at(loaded.volumes.size(), -1), mesh_at(loaded.meshes.size(), -1);
  for (size_t k = 0; k < loaded.order.size(); ++k) {
    if (!keep[k] && !hidden[k]) continue;
    const ObjectRef& ref = loaded.order[k];
    if (ref.kind == ObjectKind::volume) {
      VolumeObject v = loaded.volumes[ref.index];
      if (auto it = part.bricks.find(v.name); it != part.bricks.end())
        v.clip_planes.insert(v.clip_planes.end(), it->second.bounds.begin(),
                             it->second.bounds.end());
      volume_at[ref.index] = static_cast<int>(sub.volumes.size());
      sub.order.push_back({ObjectKind::volume, volume_at[ref.index]});
      sub.volumes.push_back(std::move(v));
    } else if (ref.kind == ObjectKind::mesh) {
      MeshObject m = loaded.meshes[ref.index];
      if (hidden[k]) {  // only cuts a volume here; drawn by the rank that renders it
        m.material.opacity = 0.0f;
        m.interior.reset();
      }
      if (auto_thickness && !m.thickness) m.thickness = pitch;
      mesh_at[ref.index] = static_cast<int>(sub.meshes.size());
      sub.order.push_back({ObjectKind::mesh, mesh_at[ref.index]});
      sub.meshes.push_back(std::move(m));
    } else if (ref.kind == ObjectKind::streamlines) {
      StreamlineObject o = loaded.streamlines[ref.index];  // auto thickness: 0 in any scene
      sub.order.push_back({ObjectKind::streamlines, static_cast<int>(sub.streamlines.size())});
      sub.streamlines.push_back(std::move(o));
    } else {
      PlaneObject p = loaded.planes[ref.index];
      if (auto_thickness && !p.thickness) p.thickness = pitch;
      sub.order.push_back({ObjectKind::plane, static_cast<int>(sub.planes.size())});
      sub.planes.push_back(std::move(p));
    }
  }
  // Indices into the lists: a plane's volume goes with it (plan_partition), clip meshes were
  // kept above.
  for (PlaneObject& p : sub.planes)
    if (p.volume >= 0) p.volume = volume_at.at(static_cast<size_t>(p.volume));
  for (VolumeObject& v : sub.volumes)
    for (ClipMesh& c : v.clip_meshes) c.mesh = mesh_at.at(static_cast<size_t>(c.mesh));
  for (StreamlineObject& o : sub.streamlines)
    for (ClipMesh& c : o.clip_meshes) c.mesh = mesh_at.at(static_cast<size_t>(c.mesh));
  if (!sub.render.last_volume.empty() &&
      std::none_of(sub.volumes.begin(), sub.volumes.end(),
                   [&](const VolumeObject& v) { return v.name == sub.render.last_volume; }))
    sub.render.last_volume.clear();
  return sub;
}

}  // namespace imx
