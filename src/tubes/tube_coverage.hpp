// Silhouette coverage of tubes (render.tube_coverage): at one sample per pixel a streamline's
// tube covers the part of each pixel its radius reaches, so thin tubes stay continuous and their
// edges ramp instead of stepping. Connectomes are drawn without it.
#pragma once
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <span>

#include <glm/vec3.hpp>

#include "core/camera_model.hpp"
#include "core/ray.hpp"
#include "intermix/scene.hpp"
#include "tubes/tube_fragments.hpp"
#include "tubes/tube_geometry.hpp"

namespace imx {

// Whether a method draws tubes with silhouette coverage: render.tube_coverage "on" or "off";
// "auto" means on in the zSlab methods (`zslab_method`) and off in the others.
bool tube_coverage_on(const RenderSettings& render, bool zslab_method);

// Whether `object` can be drawn with coverage: streamlines, not a connectome.
bool coverable(const StreamlineObject& object);

// The pad (mm) a TubeGeometry needs for silhouette coverage where pixels are at most
// `widest_footprint` mm wide: half of it, rounded up to a power of 2^(1/8) so that small camera
// moves keep the same geometry.
float silhouette_pad(float widest_footprint);
// The same for `object` seen by `camera`: the footprint at the farthest corner of its bounds.
float silhouette_pad(const CameraModel& camera, const StreamlineObject& object);

// Turns silhouette coverage on in `look`, whose geometry must have been built with at least
// silhouette_pad(footprint at the farthest tube): its fragments are CoveredGathering's.
// Streamlines only (a connectome's look is left as it is).
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

// A covered crossing's fragment: the true tube's entry or exit (both at the closest approach
// for a ray that passes it), the part c of the pixel covered, alpha 1 - sqrt(1 - c * opacity).
struct CoveredFragment {
  float t, coverage, alpha, u;
  glm::vec3 normal;  // the radial direction at t, not unit length
  uint32_t segment;
  uint32_t candidate;  // which candidate made it, among one gathering's
  uint32_t entry;      // 1 for the entry, 0 for the exit
};

// Gathers the covered fragments of one ray between `lo` and `hi` from a padded geometry
// (TubeGeometry::visit_hits): each candidate, a padded tube's entry, is followed to its true
// tube. It keeps the kMaxCandidates nearest candidates and, once what their fragments let through
// in depth order (after `let_through` from earlier ones) falls below `bound`, stops looking behind
// that depth: a candidate's fragments lie at or behind its padded entry. Pure, no allocation.
class CoveredGathering final : public TubeHitVisitor {
 public:
  static constexpr size_t kMaxCandidates = 128;
  CoveredGathering(const TubeLook& look, const Ray& ray, float lo, float hi, float t_min,
                   float let_through, float bound);
  void add(const TubeHit& candidate, const TubeRunPoints& run) override;
  // The fragments kept, nearest first.
  std::span<const CoveredFragment> fragments() const { return {fragments_, count_}; }
  // Whether candidates were dropped for room while what was kept lets through at least the bound:
  // then the next gathering starts at resume_t().
  bool truncated() const;
  float resume_t() const { return candidates_[kMaxCandidates - 1].t; }
  // What the kept fragments at or in front of `t` let through, after `let_through`: all of a
  // later gathering's lie behind resume_t().
  float let_through_before(float t) const;

 private:
  struct Candidate {
    float t;  // the padded entry
    uint32_t id;
  };
  void drop_candidate(size_t k);
  void cut();  // lowers `reach` to where what the fragments let through falls below the bound
  const TubeLook& look_;
  const Ray& ray_;
  float lo_, hi_, before_, bound_;
  float product_ = 1.0f;  // what the kept fragments let through
  float cut_t_ = INFINITY;
  uint32_t next_id_ = 0;
  size_t candidate_count_ = 0, count_ = 0;
  Candidate candidates_[kMaxCandidates];           // by padded entry
  CoveredFragment fragments_[2 * kMaxCandidates];  // by depth
};

}  // namespace imx
