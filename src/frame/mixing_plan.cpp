#include "frame/mixing_plan.hpp"

#include <limits>

#include <fmt/format.h>

#include "intermix/error.hpp"

namespace imx {

MixingPlan::MixingPlan(const Scene& scene)
    : exclusive(scene.render.mixing == "exclusive"),
      rank(scene.volumes.size(), std::numeric_limits<uint8_t>::max()),
      threshold(static_cast<float>(scene.render.mixing_threshold)) {
  int next = 0;
  for (const std::vector<std::string>& group : scene.render.mixing_priority) {
    for (const std::string& name : group)
      for (size_t v = 0; v < scene.volumes.size(); ++v)
        if (scene.volumes[v].name == name) rank[v] = static_cast<uint8_t>(next);
    ++next;
  }
  for (uint8_t& r : rank)
    if (r == std::numeric_limits<uint8_t>::max()) r = static_cast<uint8_t>(next++);
  if (next > 255) throw Error(fmt::format("render.mixing_priority: {} ranks, at most 255", next));
  medium_rank = static_cast<uint8_t>(next);
}

}  // namespace imx
