// The colour bars a scene's visible colour-mapped objects ask for (render --colorbar).
#pragma once
#include <optional>
#include <vector>

#include "annotate/colour_bar.hpp"
#include "intermix/scene.hpp"

namespace imx {

// A volume's bar: its transfer function's colours over the values where it has opacity (from
// the point before the first with opacity to the point after the last), named by the volume,
// with its units. None for a hidden volume (no opacity anywhere), an iso surface (one colour) or
// a transfer function of one value (a label volume's).
std::optional<ColourBar> volume_colour_bar(const VolumeObject& volume);

// A plane's bar: the colour map over its window [centre - width/2, centre + width/2], times the
// plane's colour, and nothing below its threshold; named by the volume it shows, shown by the
// plane. None for a hidden plane, one without a volume, and a grey plane (the anatomy under the
// overlays, thresholded or not, whose bar would be a plain grey ramp).
std::optional<ColourBar> plane_colour_bar(const Scene& scene, const PlaneObject& plane);

// Every bar of the scene, in scene order. An object kind that colours by
// values (a mesh overlay) adds its own maker here.
std::vector<ColourBar> scene_colour_bars(const Scene& scene);

}  // namespace imx
