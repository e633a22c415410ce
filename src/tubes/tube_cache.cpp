#include "tubes/tube_cache.hpp"

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
  return key;
}

}  // namespace

std::shared_ptr<const TubeGeometry> TubeCache::geometry(const StreamlineObject& object) {
  std::vector<double> key = geometry_key(object);
  std::lock_guard lock(mutex_);
  if (!built_ || key != key_) {
    built_.reset();  // the old BVH goes before the new one is built: one at a time in memory
    built_ = std::make_shared<const TubeGeometry>(object);
    key_ = std::move(key);
  }
  return built_;
}

std::shared_ptr<TubeCache> make_tube_cache() {
  return std::make_shared<TubeCache>();
}

std::shared_ptr<const TubeGeometry> tube_geometry(const StreamlineObject& object) {
  if (object.cache) return object.cache->geometry(object);
  return std::make_shared<const TubeGeometry>(object);
}

}  // namespace imx
