#include "volume/preintegration_cache.hpp"

#include <algorithm>

#include "core/fnv1a.hpp"

namespace imx {

uint64_t tf_fingerprint(const TfLut& lut) {
  const std::vector<glm::vec4>& e = lut.entries();
  const float scalars[3] = {lut.lo(), lut.hi(), lut.unit_distance()};
  return Fnv1a().add_bytes(e.data(), e.size() * sizeof(glm::vec4)).add(scalars).value();
}

std::shared_ptr<const PreintegrationTable> PreintegrationCache::get(const TfLut& lut, float dt,
                                                                    float lo, float hi, int size) {
  Key key{tf_fingerprint(lut), dt, lo, hi, size};
  std::lock_guard lock(mutex_);
  for (auto it = items_.begin(); it != items_.end(); ++it)
    if (it->key == key) {
      items_.splice(items_.begin(), items_, it);
      return items_.front().table;
    }
  auto table = std::make_shared<const PreintegrationTable>(lut, dt, lo, hi, size);
  ++builds_;
  items_.push_front({key, table});
  while (items_.size() > std::max<size_t>(capacity_, 1)) items_.pop_back();
  return table;
}

size_t PreintegrationCache::builds() const {
  std::lock_guard lock(mutex_);
  return builds_;
}

}  // namespace imx
