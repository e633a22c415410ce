// What a frame of render_zslab_cached reuses (SPEC §4, reuse), decided before any tile runs from
// the stages' keys and sizes and from what the cache holds. A pure function of its input, so
// eviction, matching and the merged prefix are tested without rendering.
#pragma once
#include <cstddef>
#include <cstdint>
#include <optional>
#include <vector>

namespace imx {

// A kept slab array as the plan sees it: its key and its shape.
struct KeptArrayShape {
  uint64_t key = 0;
  size_t samples = 0;
  int capacity = 0;
};

struct ZslabReuseInput {
  // Per deferred stage k (the on-the-fly one excluded):
  std::vector<uint64_t> own_key;  // hash of the frame and the stage's own content
  std::vector<int> capacity;      // slots of its own array per sample; 0: run whole, not kept
  // chain[k]: hash of the frame and stages 0..k-1 (one more entry than own_key).
  std::vector<uint64_t> chain;
  size_t samples = 0;  // of the frame: pixels x spp
  int layers = 1;      // N: the slots of a merged array (the prefix)
  uint64_t budget = 0;
  // What the cache holds: its own arrays in its order (nullopt: dropped), and its prefix.
  std::vector<std::optional<KeptArrayShape>> kept_own;
  std::optional<KeptArrayShape> prefix;
  size_t prefix_stage = 0;  // the stage the kept prefix was merged up to
};

struct ZslabReusePlan {
  // Per deferred stage:
  std::vector<bool> keep;    // its own array is kept within the budget (else recomputed each frame)
  std::vector<int> matched;  // the kept own array it reuses (index in kept_own), or -1
  std::vector<bool> render;  // its object is rendered this frame
  size_t first = 0;          // the first stage not matched (the deferred count when none)
  size_t start = 0;          // the first stage merged: the kept prefix's stage, or 0
  bool read_prefix = false;  // the kept prefix is valid: the merges start from it
  bool write_prefix = false;  // the merged array before `first` becomes the kept prefix
  bool drop_prefix = false;   // the cache lets its prefix go (it may still be read this frame)
  uint64_t own_bytes = 0;     // the own arrays kept
  uint64_t prefix_bytes = 0;  // one merged array

  // The kept arrays this frame holds: own ones and, read or written, the prefix.
  uint64_t kept_bytes() const {
    return own_bytes + (read_prefix || write_prefix ? prefix_bytes : 0);
  }
  int stages_run() const;
  int stages_merged() const { return static_cast<int>(keep.size() - start); }
};

ZslabReusePlan plan_zslab_reuse(const ZslabReuseInput& in);

}  // namespace imx
