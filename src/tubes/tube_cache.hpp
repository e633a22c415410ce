// TubeCache: a streamline object's built tubes, kept across frames and copies of the scene.
#pragma once
#include <array>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <mutex>
#include <span>
#include <vector>

#include "intermix/scene.hpp"
#include "tubes/tube_clip_meshes.hpp"
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

  // The clip meshes of `object` resolved in `meshes` (the scene's), built again only when the
  // meshes or what they keep changed; null without clip meshes.
  std::shared_ptr<const TubeClipMeshes> clip_meshes(const StreamlineObject& object,
                                                    std::span<const MeshObject> meshes);

  // How many geometries were built (for tests).
  size_t builds() const;

 private:
  struct Entry {
    std::vector<double> key;
    std::shared_ptr<const TubeGeometry> built;
  };
  mutable std::mutex mutex_;
  std::array<Entry, 2> entries_;  // [0]: a preview, [1]: a full selection
  size_t builds_ = 0;
  std::vector<uintptr_t> clip_meshes_key_;  // mesh addresses and keep flags
  std::shared_ptr<const TubeClipMeshes> clip_meshes_;
};

// A fresh cache for a new streamline object.
std::shared_ptr<TubeCache> make_tube_cache();

// The geometry of `object`: from its cache, or built now when it has none.
std::shared_ptr<const TubeGeometry> tube_geometry(const StreamlineObject& object, float pad = 0.0f);

// The clip meshes of `object` resolved in the scene's `meshes`: from its cache, or built now
// when it has none; null without clip meshes, and for a connectome.
std::shared_ptr<const TubeClipMeshes> tube_clip_meshes(const StreamlineObject& object,
                                                       std::span<const MeshObject> meshes);

}  // namespace imx
