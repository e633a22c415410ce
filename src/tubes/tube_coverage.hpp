// Silhouette coverage of tubes (render.tube_coverage): at one sample per pixel a streamline's
// tube covers the part of each pixel its radius reaches, so thin tubes stay continuous and their
// edges ramp instead of stepping. Connectomes are drawn without it.
#pragma once
#include <cstddef>
#include <vector>

#include "core/camera_model.hpp"
#include "core/ray.hpp"
#include "intermix/scene.hpp"
#include "raster/fragment.hpp"
#include "tubes/tube_fragments.hpp"
#include "tubes/tube_geometry.hpp"

namespace imx {

// Whether a method draws tubes with silhouette coverage: render.tube_coverage "on" or "off";
// "auto" means on in the zSlab methods (`zslab_method`) and off in the others.
bool tube_coverage_on(const RenderSettings& render, bool zslab_method);

// Whether `object` can be drawn with coverage: streamlines, not a connectome.
bool coverable(const StreamlineObject& object);

// The pad (mm) a TubeGeometry needs for silhouette coverage where pixels are at most
// `widest_footprint` mm wide: half of it, rounded up to a power of two so that small camera
// moves keep the same geometry.
float silhouette_pad(float widest_footprint);
// The same for `object` seen by `camera`: the footprint at the farthest corner of its bounds.
float silhouette_pad(const CameraModel& camera, const StreamlineObject& object);

// Turns silhouette coverage on in `look`, whose geometry must have been built with at least
// silhouette_pad(footprint at the farthest tube): each crossing's fragments take the part c of
// the pixel the tube covers, alpha 1 - sqrt(1 - c * opacity), and a ray passing within
// radius + footprint / 2 of an axis gets an entry and exit at its closest approach. Streamlines
// only (a connectome's look is left as it is).
void enable_silhouette_aa(TubeLook& look, float footprint_at_0, float footprint_per_mm);
// The same with `camera`'s pixel footprint.
void enable_silhouette_aa(TubeLook& look, const CameraModel& camera);

// Draws `look`'s true tubes, hit or missed, when its geometry is padded (built for coverage and
// kept by TubeCache) but coverage is off: coverage with a footprint of 0.
void hard_tubes_through_pad(TubeLook& look);

// Several samples per pixel: each covers its share, a footprint 1/sqrt(samples) as wide.
void share_footprint(TubeLook& look, size_t samples);

// The part of a pixel of width `footprint` covered by a tube of `radius` whose axis passes at
// `distance` from the pixel's ray: a linear ramp across the silhouette, 0..1.
float tube_coverage(float radius, float distance, float footprint);

// With coverage, partly covering crossings in front let light through: the fewest fragments a
// ray keeps of an object even when it is opaque.
inline constexpr size_t kCoveredFragments = 8;
// tube_fragments_needed(object) with coverage: at least kCoveredFragments for streamlines.
size_t covered_fragments_needed(const StreamlineObject& object);

// What a candidate of the padded geometry (an entry into a padded tube) makes: the true tube's
// entry and exit, or both at the ray's closest approach to the axis when it passes the tube,
// and the part of the pixel covered (0: none, make no fragment).
struct CoveredCrossing {
  float coverage = 0.0f;
  TubeHit entry, exit;
};
CoveredCrossing covered_crossing(const TubeLook& look, const Ray& ray, const TubeHit& candidate);

// Covered crossings are found by their padded entries: sorts `out` from `first` on by depth,
// nearest first as the methods expect.
void sort_covered_fragments(std::vector<Fragment>& out, size_t first);

// Once the shaded fragments of `out` from `first` on let through less than `bound`: sorts them
// and drops those behind the one where, in depth order, what they let through falls below it.
// Returns that one's depth (INFINITY when none) and sets `let_through` to what the kept let
// through. Candidates whose padded entries lie behind it need not be asked for.
float cut_covered_fragments(std::vector<Fragment>& out, size_t first, float bound,
                            float& let_through);

}  // namespace imx
