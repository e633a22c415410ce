#include "volume/volume_marcher.hpp"

#include "volume/wide_scalar.hpp"

namespace imx {

// Out of line, so that the march is compiled once for each level (run_wide_scalar), not in
// every method that pulls slabs; a call per slab costs less than a baseline march would.
bool VolumeMarcher::next(Slab& out) {
  return run_wide_scalar(wide_, [&] { return next_on_grid(out); });
}

glm::vec4 VolumeMarcher::shade_wide(const glm::vec4& c, double front, double back,
                                    PreintegrationView::Light light) const {
  return run_wide_scalar(true, [&] { return shade(c, front, back, light); });
}

}  // namespace imx
