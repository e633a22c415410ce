// Rasterizer: every fragment of every mesh and plane at arbitrary sub-pixel sample positions.
#pragma once
#include <cstdint>
#include <memory>
#include <span>
#include <vector>

#include <glm/vec2.hpp>

#include "core/camera_model.hpp"
#include "core/parallel.hpp"
#include "intermix/scene.hpp"
#include "raster/fragment.hpp"
#include "volume/prepared_volume.hpp"

namespace imx {

// Fragments of all samples of a tile, as compressed rows: sample s owns
// fragments[offsets[s] .. offsets[s + 1]), sorted by t (ties keep scene order), or in arrival
// (triangle = scene) order when rasterized with FragmentOrder::arrival.
struct SampleFragments {
  std::vector<uint32_t> offsets;
  std::vector<Fragment> fragments;
  std::vector<uint32_t> hits;  // scratch: the tile's triangles that cover a sample

  std::span<const Fragment> of(size_t sample) const {
    return {fragments.data() + offsets[sample], fragments.data() + offsets[sample + 1]};
  }
  size_t sample_count() const { return offsets.empty() ? 0 : offsets.size() - 1; }
};

// How each sample's fragments come out: sorted by depth, or as the triangles produced them (the
// store pass of an order-dependent fragment buffer such as the k+-buffer).
enum class FragmentOrder { depth, arrival };

// Which objects a rasterizer gives fragments of: every mesh and plane that shows (all but the
// clip meshes of material opacity 0, which only cut; CSG primitives always show), or the clip
// meshes alone, unshaded (colour 0), for the clip step (SPEC §7).
enum class RasterObjects { shown, clip };

// Per mesh of `scene`: whether a RasterObjects::shown rasterizer draws it: a material opacity
// above 0 or a CSG primitive. The rest (hidden meshes, clip meshes that only cut) make no
// fragments, so a hidden object costs nothing and renders as if absent.
std::vector<bool> shown_meshes(const Scene& scene);
// Whether a RasterObjects::shown rasterizer draws a plane: an opacity above 0.
bool shown_plane(const PlaneObject& plane);

class Rasterizer {
 public:
  // Prepares every mesh and plane of the scene for the camera: camera-space triangles clipped
  // at the near plane, per-triangle setup, and bins of triangles per tile of `tile_size` pixels.
  // `volumes` are the scene's volumes in Scene::volumes order (planes with a volume sample them);
  // they are kept by pointer and must outlive the rasterizer, the scene need not.
  // A plane's height runs along `up` made perpendicular to its normal, its width along
  // cross(height, normal). Throws imx::Error naming the mesh, plane or order entry at fault.
  // Fragment object ids are Scene::order indices whichever `objects` are drawn.
  // `tube_coverage`: streamline tubes with silhouette coverage (tubes/tube_coverage.hpp).
  Rasterizer(const Scene& scene, const CameraModel& camera, std::span<const PreparedVolume> volumes,
             int tile_size, RasterObjects objects = RasterObjects::shown,
             bool tube_coverage = false);

  // Fills `out` with the fragments of every sample of `tile` (a tile of the same tile_size grid).
  // Sample s of pixel (x, y) lies at image position (x + offsets[s].x, y + offsets[s].y);
  // its index is ((y - tile.y0) * tile.width() + (x - tile.x0)) * offsets.size() + s.
  // `out` is reused between calls to avoid allocation. Offsets must lie in [0, 1]^2; coverage
  // is exact on a 1/4096-pixel grid with a watertight tie rule, depth t is exact (double) at
  // the sample's true position. Thread-safe: concurrent calls on different `out`s are fine.
  void rasterize(const TileRect& tile, std::span<const glm::vec2> offsets, SampleFragments& out,
                 FragmentOrder order = FragmentOrder::depth) const;

  int tile_size() const { return tile_size_; }
  // Triangles after near-plane and guard-band clipping that overlap the image (a mesh's
  // degenerate or edge-on triangles included: they make no fragments).
  size_t triangle_count() const;

 private:
  struct Impl;
  std::shared_ptr<const Impl> impl_;
  int tile_size_;
};

}  // namespace imx
