// PreintegrationCache: the pre-integration tables of recent (TF, step) pairs, rebuilt on change.
#pragma once
#include <cstddef>
#include <cstdint>
#include <list>
#include <memory>
#include <mutex>

#include "volume/preintegration_table.hpp"
#include "volume/tf_lut.hpp"

namespace imx {

// A 64-bit FNV-1a hash of everything TfLut::lookup depends on: entries, range, unit distance.
uint64_t tf_fingerprint(const TfLut& lut);

// Small LRU keyed by (TF fingerprint, dt, value range, size): a TF edit or a new step misses
// and builds; frames that change neither reuse the table. Thread-safe; tables are immutable and
// shared, so a table handed out stays valid after eviction.
class PreintegrationCache {
 public:
  explicit PreintegrationCache(size_t capacity = 4) : capacity_(capacity) {}

  std::shared_ptr<const PreintegrationTable> get(const TfLut& lut, float dt, float lo, float hi,
                                                 int size = PreintegrationTable::kDefaultSize);
  std::shared_ptr<const PreintegrationTable> get(const TfLut& lut, float dt) {
    return get(lut, dt, lut.lo(), lut.hi());
  }

  size_t builds() const;  // tables built so far (misses)

 private:
  struct Key {
    uint64_t tf;
    float dt, lo, hi;
    int size;
    bool operator==(const Key&) const = default;
  };
  struct Item {
    Key key;
    std::shared_ptr<const PreintegrationTable> table;
  };

  size_t capacity_;
  size_t builds_ = 0;
  std::list<Item> items_;  // most recently used first
  mutable std::mutex mutex_;
};

}  // namespace imx
