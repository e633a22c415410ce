// TubeGeometry: a streamline object's tubes, exact capsules in a TubeBvh.
#pragma once
#include <cstddef>
#include <cstdint>
#include <memory>
#include <span>
#include <vector>

#include <glm/geometric.hpp>
#include <glm/vec3.hpp>

#include "core/ray.hpp"
#include "intermix/scene.hpp"
#include "tubes/tube_bvh.hpp"

namespace imx {

// Bytes TubeGeometry holds for `segments` segments of `streamlines` streamlines: a segment
// index and a copied point each, and per run of at most TubeBvh::kRunSegments segments its
// header and three more points and its share of the nodes (under 32 bytes, measured 22).
inline uint64_t tube_bytes(uint64_t streamlines, uint64_t segments) {
  return segments * (4 + 12) + (segments / TubeBvh::kRunSegments + streamlines) * (4 * 12 + 32);
}

class TubeGeometry {
 public:
  // Every segment of the streamlines `object` selects (tube_selection.hpp), of its radius; or,
  // for a connectome object, its shown edges as tubes and nodes as spheres
  // (connectome_primitives.hpp), each of its own radius and colour.
  // Throws imx::Error naming the object when the memory budget refuses.
  // `pad` mm widens the streamlines' tubes in the hierarchy (not a connectome's) so that rays
  // passing within radius + pad of an axis are candidates for silhouette coverage
  // (tube_coverage.hpp); the true radius is radius(), the one contains() tests.
  explicit TubeGeometry(const StreamlineObject& object, float pad = 0.0f);
  ~TubeGeometry();
  TubeGeometry(const TubeGeometry&) = delete;
  TubeGeometry& operator=(const TubeGeometry&) = delete;

  // The hits of `ray` with t_min < t < t_max, nearest first: the out.size() nearest of them.
  // Returns how many were found. Thread-safe.
  size_t nearest_hits(const Ray& ray, float t_min, float t_max, std::span<TubeHit> out) const {
    return bvh_.nearest_hits(ray, t_min, t_max, out);
  }
  // The hits `visitor` still wants, in no particular order (TubeBvh::visit_hits).
  void visit_hits(const Ray& ray, TubeHitVisitor& visitor) const { bvh_.visit_hits(ray, visitor); }

  // Whether `point` lies inside a tube (within its radius of a segment's axis, or of a
  // connectome sphere's centre); if so and `where` is given, a hit naming the nearest such
  // primitive, with the normal from its axis to the point and t = 0. Thread-safe.
  bool contains(const glm::vec3& point, TubeHit* where = nullptr) const {
    if (pad_ == 0.0f) return bvh_.contains(point, where);
    // Padded: the nearest axis within radius + pad, inside when within the true radius.
    TubeHit nearest;
    if (!bvh_.contains(point, &nearest) || !(glm::length(nearest.normal) <= radius_)) return false;
    if (where) *where = nearest;
    return true;
  }

  // The first of a segment's two points, an index into the object's Streamlines::points.
  uint32_t first_point(uint32_t segment) const { return segment_points_[segment]; }
  // The streamline a segment belongs to (Streamlines index).
  uint32_t streamline(uint32_t segment) const;
  size_t segment_count() const { return segment_points_.size(); }
  // A connectome's: its primitives are its tubes, then its spheres, each of one colour.
  bool is_connectome() const { return connectome_; }
  size_t primitive_count() const { return primitive_colors_.size(); }
  const glm::vec3& primitive_color(uint32_t primitive) const {
    return primitive_colors_[primitive];
  }
  size_t streamline_count() const { return selected_count_; }
  float radius() const { return radius_; }
  float pad() const { return pad_; }
  // Resident bytes of the segment indices and the hierarchy (and a connectome's primitives).
  size_t bytes() const { return bytes_; }

 private:
  void build_connectome(const StreamlineObject& object);
  std::shared_ptr<const Streamlines> streamlines_;
  std::vector<uint32_t> segment_points_;  // per segment, its first point
  size_t selected_count_ = 0;
  size_t bytes_ = 0;
  bool connectome_ = false;
  float radius_ = 0.0f;  // the streamlines' true radius, mm
  float pad_ = 0.0f;     // added to it in the hierarchy
  // A connectome's primitives: a tube's two ends or a sphere's centre twice (a capsule of
  // no length), the radius and the colour (linear RGB) of each.
  std::vector<glm::vec3> primitive_points_;
  std::vector<float> primitive_radii_;
  std::vector<glm::vec3> primitive_colors_;
  TubeBvh bvh_;
};

}  // namespace imx
