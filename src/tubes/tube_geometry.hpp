// TubeGeometry: a streamline object's tubes as exact round linear curves in an Embree BVH.
#pragma once
#include <cstddef>
#include <cstdint>
#include <memory>
#include <span>
#include <vector>

#include <glm/vec3.hpp>

#include "core/ray.hpp"
#include "intermix/scene.hpp"

namespace imx {

// One crossing of a ray with a tube's surface.
struct TubeHit {
  float t = 0.0f;          // along the ray, mm
  glm::vec3 normal{0.0f};  // the surface's geometric normal, not unit length
  uint32_t segment = 0;    // TubeGeometry segment index; a connectome's primitive index
  float u = 0.0f;          // where along the segment, 0 at its first point, 1 at its second
};

// Bytes TubeGeometry holds for `segments` segments over `points` points: float4 vertices,
// index and flags, and Embree's BVH (about 34 bytes per segment, measured).
inline uint64_t tube_bytes(uint64_t points, uint64_t segments) {
  return points * 16 + segments * (4 + 1 + 34);
}

class TubeGeometry {
 public:
  // Every segment of the streamlines `object` selects (tube_selection.hpp), of its radius; or,
  // for a connectome object, its shown edges as tubes and nodes as spheres
  // (connectome_primitives.hpp), each of its own radius and colour.
  // Throws imx::Error naming the object when the memory budget or Embree refuses.
  // `pad` mm widens the streamlines' Embree tubes (not a connectome's) so that rays passing
  // within radius + pad of an axis are candidates for silhouette coverage (tube_fragments.hpp);
  // the true radius is radius().
  explicit TubeGeometry(const StreamlineObject& object, float pad = 0.0f);
  ~TubeGeometry();
  TubeGeometry(const TubeGeometry&) = delete;
  TubeGeometry& operator=(const TubeGeometry&) = delete;

  // The hits of `ray` with t_min < t < t_max, nearest first: the out.size() nearest of them.
  // Returns how many were found. Thread-safe.
  size_t nearest_hits(const Ray& ray, float t_min, float t_max, std::span<TubeHit> out) const;

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
  // Resident bytes of the vertices, segment indices and the BVH.
  size_t bytes() const { return bytes_; }

 private:
  struct Embree;
  void build_connectome(const StreamlineObject& object);
  std::unique_ptr<Embree> embree_;
  std::shared_ptr<const Streamlines> streamlines_;
  std::vector<uint32_t> segment_points_;  // the Embree index buffer
  size_t selected_count_ = 0;
  size_t bytes_ = 0;
  bool connectome_ = false;
  float radius_ = 0.0f;                      // the streamlines' true radius, mm
  float pad_ = 0.0f;                         // added to it in the Embree vertices
  std::vector<glm::vec3> primitive_colors_;  // a connectome's, linear RGB
  uint32_t sphere_geometry_ = ~0u;           // its spheres' Embree geometry, if any
  uint32_t sphere_base_ = 0;                 // the primitive index of its first sphere
};

}  // namespace imx
