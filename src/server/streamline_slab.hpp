// Streamlines on a reading view, as MRtrix's mrview shows them: the parts of the drawn
// streamlines within half a slab of the view's plane, as lines in their colours over the slice.
#pragma once
#include <cstddef>

#include "frame/slice_view.hpp"
#include "intermix/image.hpp"
#include "intermix/scene.hpp"

namespace imx::server {

// The slab a reading view shows streamlines from when the page names none, in mm.
inline constexpr double kDefaultStreamlineSlab = 2.0;

// Draws over `image` (the view's, linear like a render) the segments of the streamlines `object`
// draws (its stride, minimum length and regions) clipped to |distance from the view's plane| <=
// slab / 2: lines `line_px` pixels wide in the object's colouring (as its tubes have it, before
// lighting), over the slice with the object's opacity. Draws at most `max_segments` segments;
// returns how many it drew. Throws imx::Error when the colouring names values the streamlines
// lack.
size_t draw_streamline_slab(Image& image, const SliceView& view, const StreamlineObject& object,
                            double slab, int line_px, size_t max_segments = 1000000);

}  // namespace imx::server
