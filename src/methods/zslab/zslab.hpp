// The zSlab methods (SPEC §4): `zslab` (full image-level: every object deferred into ping-pong
// ZT-buffers) and `zslab-hybrid` (the last volume cast on the fly against the stored slabs).
#pragma once
#include <cstdint>
#include <memory>
#include <vector>

#include "intermix/image.hpp"
#include "intermix/render.hpp"
#include "intermix/scene.hpp"
#include "slab/zslab_params.hpp"

namespace imx {

// Stateless entries: stages run tile by tile on tile-local buffers, nothing is kept.
Image render_zslab(const Scene& scene, int spp, const RenderOptions& options);
Image render_zslab_hybrid(const Scene& scene, int spp, const RenderOptions& options);

class ZtBuffer;

// The full pipeline's output before its final composite, for compositing elsewhere (distributed
// rendering): every stage deferred, each sample's merged array stored in `arrays` (resized to
// width * height * spp samples: pixels in row order, a pixel's samples one after the other).
// accumulate() of each sample's array, averaged per pixel, gives render_zslab's image.
void render_zslab_arrays(const Scene& scene, int spp, const RenderOptions& options,
                         ZtBuffer& arrays);

class KeptSlabArrays;

// Object-level reuse (SPEC §4): per deferred stage the object's own slab array, keyed by a hash
// of the frame (camera, settings) and that stage's own content only, plus one merged array of
// the stages before `prefix_stage`, so an edit re-renders one object and re-runs the merges after.
struct ZslabStageCache {
  struct Kept {
    uint64_t key = 0;
    std::shared_ptr<KeptSlabArrays> slabs;                // null: not kept
    std::vector<std::shared_ptr<const void>> keep_alive;  // data whose identity the key hashed
  };
  std::vector<Kept> own;  // in stage order of the frame that filled them
  Kept prefix;            // the merged (stored) array before stage prefix_stage
  size_t prefix_stage = 0;
  uint64_t budget_bytes = uint64_t{512} << 20;  // kept arrays at most; the largest go first
  uint64_t last_key = 0;                        // the on-the-fly stage's key, last frame
  uint64_t image_key = 0;
  std::shared_ptr<const Image> image;  // the last frame, when nothing it read has changed

  size_t kept_bytes() const;
};

struct ZslabStats {
  int stages = 0;                       // stages of the frame (the on-the-fly one included)
  int stages_run = 0;                   // stages whose object was rendered (the rest: kept)
  int stages_merged = 0;                // deferred stages merged again from kept own arrays
  bool recast_unchanged = false;        // zslab-hybrid re-cast its last volume, unchanged
  double stream_bytes_per_pixel = 0.0;  // tile-local buffers per pixel: (2N + M) slabs
  double kept_bytes_per_pixel = 0.0;    // whole-frame arrays kept for reuse
};

class ZslabFrame;

// One volume alone (volume_packets_apply) with rgba32f slabs: nothing is stored to intermix
// with, so a sample's slabs only composite (greedy merges and the kernel keep the composite
// exact) and the rays can share mdvr's vector lanes, each piece shaded where its light comes
// from as the slab methods' marcher does. The image equals the per-sample pipeline's up to float
// rounding (MdvrPackets.SlabMethodsOnOneVolumeSameImageAsTheirPipeline); real CT 3-4x faster.
bool zslab_in_packets(const ZslabFrame& z);
Image render_zslab_packets(const ZslabFrame& z, const RenderOptions& options);

// The same pipeline with object-level reuse: recomputes the own arrays of the stages whose
// object changed, merges kept and new own arrays tile by tile, and refills `cache` within its
// budget. The image equals render_zslab(_hybrid) of the same scene bit for bit.
Image render_zslab_cached(const Scene& scene, int spp, const RenderOptions& options, bool hybrid,
                          ZslabStageCache& cache, ZslabStats* stats = nullptr);

// The per-sample settings render.layers, rt_layers, peel_layers, interpolation, ert_threshold
// and overflow give (without their range checks, which the pipeline makes).
ZslabParams zslab_params(const RenderSettings& render);

// Memory of the stateless (tile-streamed) pipeline per sample: (2N + M) slabs of the format,
// plus one flag bit.
double zslab_stream_bytes_per_sample(const RenderSettings& render);

}  // namespace imx
