// ClipPlan: a scene's clip geometry made ready for one frame (SPEC §7): a winding per clip mesh
// and, per volume, which of them must and must not enclose a sample.
#pragma once
#include <cstdint>
#include <vector>

#include "frame/clip_intervals.hpp"
#include "intermix/scene.hpp"

namespace imx {

class ClipPlan {
 public:
  // Throws imx::Error naming the volume for a clip mesh that is not one of the scene's meshes,
  // and for more than kMaxClipMeshes different clip meshes. Closedness is the scene loader's
  // check (a mesh that is not closed has no inside).
  explicit ClipPlan(const Scene& scene);

  // No volume of the scene is clipped.
  bool empty() const { return !any_; }
  bool clips(size_t volume) const { return view().clips(volume); }
  ClipView view() const { return {slot_of_object_, rule_}; }

 private:
  std::vector<int8_t> slot_of_object_;  // Scene::order index -> clip mesh number
  std::vector<ClipState> rule_;         // per volume
  bool any_ = false;
};

}  // namespace imx
