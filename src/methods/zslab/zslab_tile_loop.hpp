// What the zSlab pipeline's tile loops share (zslab.cpp: stateless, zslab_cached.cpp: with reuse):
// the tile size, the deferred stages' end, the samples of a tile in order, their clip rows.
#pragma once
#include <cstddef>
#include <span>
#include <vector>

#include "core/parallel.hpp"
#include "intermix/render.hpp"
#include "methods/zslab/zslab_frame.hpp"

namespace imx::zslab_tiles {

inline constexpr int kTileSize = 16;

// Index of the first stage that is not stored (the on-the-fly one), or stages.size().
inline size_t deferred_end(const ZslabFrame& z) {
  size_t k = 0;
  while (k < z.stages.size() && !z.stages[k].on_the_fly) ++k;
  return k;
}

// Calls fn(x, y, ray, sample index in the tile) for every sample of the tile, row by row.
template <class Fn>
void for_each_sample(const ZslabFrame& z, const TileRect& tile, const Fn& fn) {
  size_t i = 0;
  for (int y = tile.y0; y < tile.y1; ++y)
    for (int x = tile.x0; x < tile.x1; ++x)
      for (const glm::vec2& o : z.offsets) {
        fn(x, y, z.frame.camera.ray(x + o.x, y + o.y), i);
        ++i;
      }
}

// for_each_sample without the camera rays, for stages that do not read them (surfaces: their
// fragments come from the rasterizer): fn(x, y, sample index in the tile). A ray per sample and
// stage was 39% of zslab-hybrid's frame on torus-planes (130 surface stages).
template <class Fn>
void for_each_sample_index(const ZslabFrame& z, const TileRect& tile, const Fn& fn) {
  const size_t per_pixel = z.offsets.size();
  size_t i = 0;
  for (int y = tile.y0; y < tile.y1; ++y)
    for (int x = tile.x0; x < tile.x1; ++x)
      for (size_t o = 0; o < per_pixel; ++o) fn(x, y, i++);
}

// A tile's own volume arrays for ZslabFrame::own_volume_slabs: `layers` slots per sample.
struct OwnVolumeSlabs {
  std::vector<Slab> slots;
  std::vector<SlabList> lists;
  OwnVolumeSlabs(size_t samples, int layers) : slots(samples * static_cast<size_t>(layers)) {
    lists.reserve(samples);
    for (size_t i = 0; i < samples; ++i)
      lists.emplace_back(std::span<Slab>(slots).subspan(i * static_cast<size_t>(layers),
                                                        static_cast<size_t>(layers)));
  }
};

inline void report(const RenderOptions& options, int done, int total) {
  if (options.progress) options.progress(static_cast<double>(done) / total);
}

// Whether stage k (the on-the-fly one when k is past the deferred stages) casts a clipped volume.
inline bool clipped_stage(const ZslabFrame& z, size_t k) {
  return k < z.stages.size() && z.stages[k].kind == ZslabStage::Kind::volume &&
         z.frame.clip.clips(z.stages[k].volume);
}

// Sample i's clip-mesh fragments, when `clip` holds the tile's.
inline std::span<const Fragment> clip_row(const SampleFragments& clip, bool have, size_t i) {
  return have ? clip.of(i) : std::span<const Fragment>();
}

}  // namespace imx::zslab_tiles
