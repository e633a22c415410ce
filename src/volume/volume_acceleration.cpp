#include "volume/volume_acceleration.hpp"

#include <algorithm>
#include <cmath>
#include <list>
#include <mutex>
#include <variant>

#include "core/fnv1a.hpp"
#include "intermix/limits.hpp"
#include "intermix/scene.hpp"
#include "volume/brick_min_max.hpp"
#include "volume/label_classifier.hpp"
#include "volume/preintegration_cache.hpp"
#include "volume/tf_emptiness.hpp"

namespace imx {

namespace {

// A small LRU of values derived from a voxel array (and a key), dropped when the array dies:
// weak_ptr identity, so a new array at a recycled address never hits a stale entry.
template <class Key, class Value>
class PerVolumeCache {
 public:
  explicit PerVolumeCache(size_t capacity) : capacity_(capacity) {}

  template <class Build>
  std::shared_ptr<const Value> get(const std::shared_ptr<const VolumeData>& data, const Key& key,
                                   Build&& build) {
    std::lock_guard lock(mutex_);
    for (auto it = items_.begin(); it != items_.end();) {
      std::shared_ptr<const VolumeData> owner = it->data.lock();
      if (!owner) {
        it = items_.erase(it);
        continue;
      }
      if (owner == data && it->key == key) {
        items_.splice(items_.begin(), items_, it);
        return items_.front().value;
      }
      ++it;
    }
    auto value = std::make_shared<const Value>(build());
    items_.push_front({data, key, value});
    while (items_.size() > capacity_) items_.pop_back();
    return value;
  }

 private:
  struct Item {
    std::weak_ptr<const VolumeData> data;
    Key key;
    std::shared_ptr<const Value> value;
  };
  size_t capacity_;
  std::list<Item> items_;
  std::mutex mutex_;
};

struct OccupancyKey {
  glm::ivec3 brick_shape;
  uint64_t tf;
  bool operator==(const OccupancyKey&) const = default;
};

// A label map's occupancy key: which labels show (the salt keeps it apart from TF keys).
uint64_t label_fingerprint(const LabelMap& m) {
  Fnv1a h;
  h.add(uint64_t{0x6c6162656c73}).add(m.palette_unlisted).add(m.entries.size());
  for (const LabelEntry& e : m.entries) h.add(e.value).add(e.visible && e.opacity > 0.0f);
  return h.value();
}

}  // namespace

MarchSettings MarchSettings::from(const RenderSettings& render) {
  MarchSettings s;
  s.skip = render.skipping == "none"     ? SkipMode::none
           : render.skipping == "bricks" ? SkipMode::bricks
                                         : SkipMode::distance;
  s.classification =
      render.classification == "post" ? Classification::post : Classification::preintegrated;
  s.gradients = render.gradients == "on-the-fly"    ? GradientSource::on_the_fly
                : render.gradients == "precomputed" ? GradientSource::precomputed
                                                    : GradientSource::automatic;
  s.brick_size = render.brick_size;
  return s;
}

namespace {

uint64_t voxel_bytes(const VolumeData& data) {
  return std::visit([&](const auto& b) -> uint64_t { return data.voxel_count() * sizeof(b[0]); },
                    data.voxels);
}

}  // namespace

bool precomputes_gradients(GradientSource source, const VolumeData& data) {
  if (source != GradientSource::automatic) return source == GradientSource::precomputed;
  const uint64_t copy = GradientVolume::bytes_at_most(data);
  return copy <= kGradientCopyAllowance + voxel_bytes(data) / 4 &&
         copy <= input_limits().max_memory / 4;
}

bool has_non_finite_voxels(const std::shared_ptr<const VolumeData>& data) {
  if (!data || data->type() != VoxelType::f32) return false;
  static PerVolumeCache<int, bool> scanned(64);  // a flag each: keep many
  return *scanned.get(data, 0, [&] { return non_finite_count(*data) > 0; });
}

VolumeAcceleration accelerate(const VolumeObject& v, const TfLut& lut, float step,
                              const MarchSettings& settings) {
  static PerVolumeCache<glm::ivec3, BrickMinMax> ranges(8);
  static PerVolumeCache<OccupancyKey, BrickOccupancy> occupancies(16);
  static PerVolumeCache<int, GradientVolume> gradients(4);
  static PreintegrationCache tables(16);

  VolumeAcceleration a;
  a.skip = settings.skip;
  const AnyGrid grid(*v.data);
  // Built once per voxel array: skipping reads it, and it gives the data range without a scan.
  // Bricks are near cubes in the world (BrickGrid::shape_for): the object's index steps in mm.
  const glm::dmat4& m = v.index_to_world;
  const glm::dvec3 spacing(glm::length(glm::dvec3(m[0])), glm::length(glm::dvec3(m[1])),
                           glm::length(glm::dvec3(m[2])));
  const glm::ivec3 shape = BrickGrid::shape_for(settings.brick_size, spacing, v.data->dims);
  std::shared_ptr<const BrickMinMax> r =
      ranges.get(v.data, shape, [&] { return BrickMinMax(grid, shape); });
  if (v.labels) {  // no TF tables: occupancy by the visible labels only (label_classifier.hpp)
    if (settings.skip == SkipMode::none) return a;
    a.ranges = r;
    const LabelLooks looks(*v.labels);
    a.occupancy = occupancies.get(v.data, OccupancyKey{shape, label_fingerprint(*v.labels)}, [&] {
      return BrickOccupancy(*r, [&](float lo, float hi) { return !looks.any_shown_in(lo, hi); });
    });
    return a;
  }
  if (settings.skip != SkipMode::none) {
    a.ranges = r;
    a.emptiness = std::make_shared<const TfEmptiness>(lut);
    a.occupancy = occupancies.get(v.data, OccupancyKey{shape, tf_fingerprint(lut)},
                                  [&] { return BrickOccupancy(*r, *a.emptiness); });
  }
  if (settings.classification == Classification::preintegrated) {
    // The table spans the data as well as the TF, so ramps beyond the TF points integrate the
    // constant ends instead of being clamped.
    float t_lo = lut.lo(), t_hi = lut.hi();
    for (glm::vec2 b : r->ranges())
      if (std::isfinite(b.x) && std::isfinite(b.y)) {
        t_lo = std::min(t_lo, b.x);
        t_hi = std::max(t_hi, b.y);
      }
    if (!(t_hi > t_lo)) t_hi = t_lo + 1.0f;
    a.preint = tables.get(lut, step, t_lo, t_hi);
  }
  if (v.shading.enabled && precomputes_gradients(settings.gradients, *v.data))
    a.gradients = gradients.get(v.data, 0, [&] { return GradientVolume(grid); });
  return a;
}

std::vector<ResidentPart> resident_parts(const VolumeObject& v, const VolumeAcceleration& a) {
  auto size = [](const auto& part) -> uint64_t { return part ? part->bytes() : 0; };
  const VolumeData& data = *v.data;
  std::vector<ResidentPart> parts = {{"voxels", voxel_bytes(data)}};
  if (data.colours) parts.push_back({"colours", data.colours->rgb.capacity()});
  parts.push_back({"gradients", size(a.gradients)});
  parts.push_back({"brick ranges", size(a.ranges)});
  parts.push_back({"brick occupancy", size(a.occupancy)});
  parts.push_back({"TF emptiness", size(a.emptiness)});
  parts.push_back({"pre-integration table", size(a.preint)});
  return parts;
}

}  // namespace imx
