// A glass brain's panel: a map's largest value (or magnitude) along the view's normal through a
// box, in its transfer function's colours over white, with the outline of the anatomy seen the
// same way (where its voxels above the background end) in grey, as nilearn's plot_glass_brain.
#pragma once
#include <optional>

#include "figure/figure_extent.hpp"
#include "frame/slice_view.hpp"
#include "intermix/image.hpp"
#include "intermix/scene.hpp"

namespace imx {

struct GlassOutline {
  const VolumeObject* anatomy;
  double background;  // background_level(*anatomy)
};

// The projection of `map` through `box` along `view`'s normal, on `view`'s pixels.
Image glass_projection(const VolumeObject& map, const SliceView& view, const WorldBox& box,
                       bool plot_abs, const std::optional<GlassOutline>& outline);

}  // namespace imx
