// MixingPlan: how one frame mixes co-located volume samples (SPEC §5): inclusive by M1, or
// exclusive by the priority ranks of render.mixing_priority.
#pragma once
#include <cstdint>
#include <span>
#include <vector>

#include "intermix/scene.hpp"

namespace imx {

// What the kernels read of a MixingPlan.
struct MixingView {
  bool exclusive = false;
  std::span<const uint8_t> rank;  // per Scene::volumes entry; lower wins
  uint8_t medium_rank = 0;        // CSG interior media, after every volume
  float threshold = 0.0f;         // TF opacity per unit_distance a winner exceeds
};

struct MixingPlan {
  bool exclusive = false;
  std::vector<uint8_t> rank;
  uint8_t medium_rank = 0;
  float threshold = 0.0f;

  // Groups of render.mixing_priority take ranks 0, 1, ... in order; volumes it does not name
  // follow one by one in scene order (all of them, in scene order, when it is empty).
  explicit MixingPlan(const Scene& scene);
  MixingView view() const { return {exclusive, rank, medium_rank, threshold}; }
};

}  // namespace imx
