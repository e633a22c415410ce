// The zSlab methods (SPEC §4): `zslab` (full image-level: every object deferred into ping-pong
// ZT-buffers) and `zslab-hybrid` (the last volume cast on the fly against the stored slabs).
#pragma once
#include <cstdint>
#include <memory>
#include <vector>

#include "intermix/image.hpp"
#include "intermix/render.hpp"
#include "intermix/scene.hpp"

namespace imx {

class ZtBuffer;

// Stateless entries: stages run tile by tile on tile-local buffers, nothing is kept.
Image render_zslab(const Scene& scene, int spp, const RenderOptions& options);
Image render_zslab_hybrid(const Scene& scene, int spp, const RenderOptions& options);

// Whole-frame stage outputs kept between frames, keyed by a hash of everything each stage read
// (its objects, every earlier stage, camera and settings). Slot k belongs to stage k.
struct ZslabStageCache {
  struct Entry {
    uint64_t key = 0;
    std::shared_ptr<const ZtBuffer> output;               // null: not kept
    std::vector<std::shared_ptr<const void>> keep_alive;  // data whose identity the key hashed
  };
  std::vector<Entry> stages;
  uint64_t image_key = 0;
  std::shared_ptr<const Image> image;  // the last frame, when nothing it read has changed
};

struct ZslabStats {
  int stages = 0;                       // stages of the frame (the on-the-fly one included)
  int stages_run = 0;                   // stages that ran (the others came from the cache)
  double stream_bytes_per_pixel = 0.0;  // tile-local buffers per pixel: (2N + M) slabs
  double kept_bytes_per_pixel = 0.0;    // whole-frame stage outputs kept for reuse
};

// The same pipeline run stage by stage over the whole frame, reusing and refilling `cache`.
Image render_zslab_cached(const Scene& scene, int spp, const RenderOptions& options, bool hybrid,
                          ZslabStageCache& cache, ZslabStats* stats = nullptr);

// Memory of the stateless (tile-streamed) pipeline per sample: (2N + M) slabs of the format,
// plus one flag bit.
double zslab_stream_bytes_per_sample(const RenderSettings& render);

}  // namespace imx
