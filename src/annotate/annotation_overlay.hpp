// A scene's annotations (rulers, angles, ROIs) drawn over a finished render of it: their lines
// projected through the scene's camera, each labelled with what it measures (docs/viewer.md).
#pragma once
#include "annotate/text_raster.hpp"
#include "intermix/image.hpp"
#include "intermix/scene.hpp"
#include "scene/annotation.hpp"

namespace imx {

// The colour annotations are drawn in (linear RGB): a yellow that shows on grey and on colour.
inline constexpr float kAnnotationColour[3] = {1.0f, 0.65f, 0.05f};

// Draws `annotations` (of `scene`, whose volumes ROIs measure) over `image` (a render of `scene`
// at its size): lines 2 px
// wide (anti-aliased), the parts behind the eye left out, and with `text` each one's
// measurement_text beside its last point (none without `text`). Throws imx::Error as measure()
// does.
void draw_annotations(Image& image, const Scene& scene, const std::vector<Annotation>& annotations,
                      const TextRaster* text);

// One anti-aliased segment from a to b (pixel coordinates, pixel centres at +0.5), `width` px
// wide, over `image` in `colour` (premultiplied "over").
void draw_segment(Image& image, glm::dvec2 a, glm::dvec2 b, double width, const glm::vec3& colour);

}  // namespace imx
