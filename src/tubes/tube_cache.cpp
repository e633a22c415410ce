#include "tubes/tube_cache.hpp"

#include <algorithm>
#include <bit>
#include <cstdint>

namespace imx {
namespace {

// Everything the geometry depends on, as numbers (pointers by value: the data is immutable).
std::vector<double> geometry_key(const StreamlineObject& o) {
  auto address = [](const void* p) { return static_cast<double>(reinterpret_cast<uintptr_t>(p)); };
  std::vector<double> key = {address(o.streamlines.get()), o.radius, static_cast<double>(o.stride),
                             o.min_length};
  for (const StreamlineRegion& r : o.regions)
    key.insert(key.end(), {static_cast<double>(r.shape), r.avoid ? 1.0 : 0.0, r.center.x,
                           r.center.y, r.center.z, r.radius, address(r.labels.get()),
                           static_cast<double>(r.label), address(r.mesh.get())});
  if (o.connectome) {  // its colours are built in too
    const ConnectomeLook& c = o.connectome_look;
    key.insert(key.end(),
               {address(o.connectome.get()), c.node_scale, c.node_min, c.node_max, c.edge_scale,
                c.edge_min, c.edge_max, static_cast<double>(c.node_colormap),
                static_cast<double>(c.node_colormap_negative), static_cast<double>(c.edge_colormap),
                static_cast<double>(c.edge_colormap_negative)});
  }
  return key;
}

// Silhouette coverage works with any pad at least the one asked: a padded geometry serves pads
// down to half its own, so that a camera moving in and out rebuilds no BVH at each step, while
// frames pay for at most twice the pad they need.
// Without coverage (pad 0) any serves: the true tubes are found through the padded ones.
bool serves_pad(float built, float asked) {
  return asked > 0.0f ? built >= asked && built <= 2.0f * asked : true;
}

}  // namespace

int preview_stride(const StreamlineObject& object) {
  const size_t count = object.streamlines ? object.streamlines->count() : 0;
  const size_t stride = std::max<size_t>(std::max(object.stride, 1),
                                         (count + kPreviewStreamlines - 1) / kPreviewStreamlines);
  return static_cast<int>(std::min<size_t>(stride, 1 << 30));
}

std::shared_ptr<const TubeGeometry> TubeCache::geometry(const StreamlineObject& object, float pad) {
  std::vector<double> key = geometry_key(object);
  // The slot by what the stride lets through at most, known before anything is built.
  const size_t count = object.streamlines ? object.streamlines->count() : 0;
  const size_t stride = static_cast<size_t>(std::max(object.stride, 1));
  Entry& entry = entries_[(count + stride - 1) / stride <= kPreviewStreamlines ? 0 : 1];
  std::lock_guard lock(mutex_);
  if (!entry.built || key != entry.key || !serves_pad(entry.built->pad(), pad)) {
    entry.built.reset();  // the old BVH goes before the new one is built: one at a time in memory
    entry.built = std::make_shared<const TubeGeometry>(object, pad);
    entry.key = std::move(key);
    ++builds_;
  }
  return entry.built;
}

std::shared_ptr<const TubeClipMeshes> TubeCache::clip_meshes(const StreamlineObject& object,
                                                             std::span<const MeshObject> meshes) {
  std::vector<uintptr_t> key;
  for (const ClipMesh& c : object.clip_meshes) {
    const bool known = c.mesh >= 0 && static_cast<size_t>(c.mesh) < meshes.size();
    key.push_back(known ? reinterpret_cast<uintptr_t>(meshes[c.mesh].mesh.get()) : 0);
    key.push_back(c.keep_inside ? 1 : 0);
  }
  std::lock_guard lock(mutex_);
  if (!clip_meshes_ || key != clip_meshes_key_) {
    clip_meshes_ = make_tube_clip_meshes(object, meshes);  // it holds the meshes it keys
    clip_meshes_key_ = std::move(key);
  }
  return clip_meshes_;
}

size_t TubeCache::builds() const {
  std::lock_guard lock(mutex_);
  return builds_;
}

std::shared_ptr<TubeCache> make_tube_cache() {
  return std::make_shared<TubeCache>();
}

std::shared_ptr<const TubeGeometry> tube_geometry(const StreamlineObject& object, float pad) {
  if (object.cache) return object.cache->geometry(object, pad);
  return std::make_shared<const TubeGeometry>(object, pad);
}

std::shared_ptr<const TubeClipMeshes> tube_clip_meshes(const StreamlineObject& object,
                                                       std::span<const MeshObject> meshes) {
  if (object.clip_meshes.empty() || object.connectome) return nullptr;
  if (object.cache) return object.cache->clip_meshes(object, meshes);
  return make_tube_clip_meshes(object, meshes);
}

}  // namespace imx
