// TubeCache: a streamline object's built tubes, kept across frames and copies of the scene.
#pragma once
#include <memory>
#include <mutex>
#include <vector>

#include "intermix/scene.hpp"
#include "tubes/tube_geometry.hpp"

namespace imx {

class TubeCache {
 public:
  // The geometry of `object`'s streamlines, radius and selection, built on the first call and
  // again only when one of them changed. Thread-safe.
  std::shared_ptr<const TubeGeometry> geometry(const StreamlineObject& object);

 private:
  std::mutex mutex_;
  std::vector<double> key_;
  std::shared_ptr<const TubeGeometry> built_;
};

// A fresh cache for a new streamline object.
std::shared_ptr<TubeCache> make_tube_cache();

// The geometry of `object`: from its cache, or built now when it has none.
std::shared_ptr<const TubeGeometry> tube_geometry(const StreamlineObject& object);

}  // namespace imx
