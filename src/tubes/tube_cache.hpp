// TubeCache: a streamline object's built tubes, kept across frames and copies of the scene.
#pragma once
#include <array>
#include <cstddef>
#include <memory>
#include <mutex>
#include <vector>

#include "intermix/scene.hpp"
#include "tubes/tube_clip.hpp"
#include "tubes/tube_geometry.hpp"

namespace imx {

// The most streamlines a preview (a viewer's moving frames) draws: a stride of the rest.
inline constexpr size_t kPreviewStreamlines = 10000;

// The stride a preview of `object` draws with: its own, or larger so that at most
// kPreviewStreamlines of its streamlines are drawn.
int preview_stride(const StreamlineObject& object);

class TubeCache {
 public:
  // The geometry of `object`'s streamlines, radius and selection, built on the first call and
  // again only when one of them changed. Two are kept: a preview's (at most kPreviewStreamlines
  // streamlines by its stride) and a full one, so that a viewer switching between moving and
  // still frames builds neither again. Thread-safe.
  // `pad`: TubeGeometry's; a geometry built with a pad from `pad` to 4 * `pad` serves, and any
  // for 0 (hard_tubes_through_pad in tube_coverage.hpp draws the true tubes through it).
  std::shared_ptr<const TubeGeometry> geometry(const StreamlineObject& object, float pad = 0.0f);

  // The clip planes of `object` over `geometry` (one this cache built), built again only when
  // the planes or the geometry changed; null when the object has no clip planes.
  std::shared_ptr<const TubeClip> clip(const StreamlineObject& object,
                                       const TubeGeometry& geometry);

  // How many geometries were built (for tests).
  size_t builds() const;

 private:
  struct Entry {
    std::vector<double> key;
    std::shared_ptr<const TubeGeometry> built;
    size_t build = 0;              // which build of the cache made `built`
    std::vector<double> clip_key;  // the planes and the build `clip` was made for
    std::shared_ptr<const TubeClip> clip;
  };
  mutable std::mutex mutex_;
  std::array<Entry, 2> entries_;  // [0]: a preview, [1]: a full selection
  size_t builds_ = 0;
};

// A fresh cache for a new streamline object.
std::shared_ptr<TubeCache> make_tube_cache();

// The geometry of `object`: from its cache, or built now when it has none.
std::shared_ptr<const TubeGeometry> tube_geometry(const StreamlineObject& object, float pad = 0.0f);

// The clip planes of `object` over `geometry`: from its cache, or built now when it has none;
// null without clip planes, and for a connectome (its primitives are no streamline segments).
std::shared_ptr<const TubeClip> tube_clip(const StreamlineObject& object,
                                          const TubeGeometry& geometry);

}  // namespace imx
