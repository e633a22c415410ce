// ZslabFrame: one frame of a zSlab pipeline planned as stages (SPEC §4): the object order, the
// per-stage inputs (rasterizer, thickness, volume step) and what one stage does to one sample.
#pragma once
#include <cstdint>
#include <memory>
#include <span>
#include <string>
#include <vector>

#include <glm/vec2.hpp>

#include "core/ray.hpp"
#include "frame/clip_intervals.hpp"
#include "frame/frame_setup.hpp"
#include "intermix/scene.hpp"
#include "methods/zslab/zslab_kernel.hpp"
#include "raster/rasterizer.hpp"
#include "slab/zt_buffer.hpp"
#include "volume/wide_scalar.hpp"

namespace imx {

// Bisections that refine an iso crossing in the volume stages.
inline constexpr int kZslabIsoBisections = 10;

struct ZslabStage {
  enum class Kind : uint8_t { surfaces, volume };
  Kind kind = Kind::surfaces;
  std::vector<uint32_t> objects;  // Scene::order indices: a group of polygon objects, or one volume
  int volume = -1;                // Scene::volumes index (volume stages)
  bool on_the_fly = false;        // the hybrid stage: cast against the stored array, not stored
  std::vector<float> thickness;   // surfaces: per object, mm, or < 0 for the pixel footprint
  std::vector<int> peel;          // surfaces: per object, the fragments a ray keeps (peel_limit)
  float step = 1.0f;              // volumes: ray step, mm
  uint64_t content = 0;           // hash of what this stage reads of its own objects
  std::string name;               // the objects' names, for messages
  // surfaces: pixels [x0, x1) x [y0, y1) outside which the stage's objects leave no fragment
  // (their world boxes' projection, a few pixels wider; the whole image when unsure)
  int x0 = 0, y0 = 0, x1 = 1 << 30, y1 = 1 << 30;
};

// render.sampling: every volume at the common step, or each at a step for its own pitch.
enum class Sampling : uint8_t { common, per_volume };

class ZslabFrame {
 public:
  // Plans the stages: polygon objects and planes in scene order (grouped so their peeled layers
  // fit the M RT layers), then volumes, render.last_volume last (empty: the one with the most
  // complex transparent structure); `hybrid` casts that last volume on the fly when it is dvr.
  ZslabFrame(const Scene& scene, int spp, bool hybrid, int sample_index = -1);

  // Builds the rasterizers of the surface stages from `first` on (before any parallel loop).
  void prepare(size_t first = 0);

  // Runs deferred stage `k` on one sample of pixel (x, y): false when the stage does not touch
  // it. `clip`: the sample's clip-mesh fragments (rasterize_clip), which a clipped volume's
  // stage needs.
  bool run_deferred(size_t k, int x, int y, const Ray& ray, std::span<const Fragment> fragments,
                    std::span<const Slab> stored, SlabList& out,
                    std::span<const Fragment> clip = {}) const;
  // Runs the on-the-fly stage `k` (or, with k out of range, just accumulates) on one sample of
  // pixel (x, y).
  glm::vec4 run_final(size_t k, int x, int y, const Ray& ray, std::span<const Slab> stored,
                      std::span<const Fragment> clip = {}) const;

  // Object-level reuse (zslab_stage_run.cpp): deferred stage `k` split into its object's own
  // slab array, which depends only on the camera and that object, and the merge of that array
  // into the stored one; merge_own(k, stored, own_slabs(k, ...)) does what run_deferred does.
  // Slots per sample of stage k's own array; 0 when the stage cannot be split (run it whole).
  int own_capacity(size_t k) const;
  // Stage k's own array for one sample into `own` (own_capacity(k) slots): its length, 0 when
  // the stage does not touch the sample.
  int own_slabs(size_t k, int x, int y, const Ray& ray, std::span<const Fragment> fragments,
                std::span<Slab> own, std::span<const Fragment> clip = {}) const;
  // Whether volume stage `k` (a deferred dvr volume no clip mesh cuts) can cast every sample of
  // a tile at once in vector lanes: own_volume_slabs.
  bool volume_stage_in_packets(size_t k) const;
  // Whether the on-the-fly stage at `k` (zslab-hybrid's last volume, no clip mesh cutting it)
  // can cast a tile's samples at once in lanes: run_final_in_lanes.
  bool final_stage_in_lanes(size_t k) const;
  // run_final(k, ...) for every sample of `tile` (for_each_sample's order) at once, sample i over
  // stored[i], into out[i]; the same colours up to float rounding. Needs final_stage_in_lanes.
  void run_final_in_lanes(size_t k, const TileRect& tile,
                          std::span<const std::span<const Slab>> stored,
                          std::span<glm::vec4> out) const;
  // Stage k's own arrays (own_slabs) for every sample of `tile` at once, lists[i] for sample i in
  // for_each_sample's order, each over its own params.layers slots; the same slabs up to float
  // rounding. Needs volume_stage_in_packets(k).
  void own_volume_slabs(size_t k, const TileRect& tile, std::span<SlabList> lists) const;
  // Merges stage k's own array into `stored` (out: N slots); false, `out` untouched, when `own`
  // is empty.
  bool merge_own(size_t k, std::span<const Slab> stored, std::span<const Slab> own,
                 SlabList& out) const;

  // Whether surface stage `k` may leave a fragment in `tile` (always true for volume stages).
  bool stage_reaches(size_t k, const TileRect& tile) const {
    const ZslabStage& st = stages[k];
    return tile.x0 < st.x1 && st.x0 < tile.x1 && tile.y0 < st.y1 && st.y0 < tile.y1;
  }

  // Fragments of surface stage `k` for every sample of `tile`; empty for other stages.
  void rasterize(size_t k, const TileRect& tile, SampleFragments& out) const;
  // The clip meshes' fragments of every sample of `tile`, sorted by depth, when a volume stage
  // prepared from the first one on is clipped; else false and `out` untouched.
  bool rasterize_clip(const TileRect& tile, SampleFragments& out) const;

  // Hash of everything all stages share (camera, image, samples, settings, lights).
  uint64_t frame_key() const { return frame_key_; }
  // Bytes of one stored slab, and of the (2N + M) slabs a tile-streamed pixel needs.
  int slab_size() const { return slab_bytes(format); }

  const Scene& scene;
  FrameSetup frame;
  ZslabParams params;
  SlabFormat format = SlabFormat::rgba32f;
  std::vector<glm::vec2> offsets;
  std::vector<ZslabStage> stages;
  std::vector<float> steps;  // per volume (Scene::volumes order), the step it is cast at, mm
  bool hybrid = true;

 private:
  // What the ray keeps of `volume` within its span, from the sample's clip fragments.
  KeptSpan kept(int volume, RayInterval span, std::span<const Fragment> clip,
                ClipPieces& pieces) const;

  std::vector<std::shared_ptr<const Rasterizer>> rasterizers_;  // per stage, surfaces only
  std::shared_ptr<const Rasterizer> clip_rasterizer_;           // the clip meshes, when needed
  float footprint_at_0_ = 0.0f, footprint_per_mm_ = 0.0f;
  uint64_t frame_key_ = 0;
  bool wide_ = wide_scalar_available();  // the per-sample work runs its x86-64-v3 copy
};

}  // namespace imx
