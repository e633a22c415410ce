// TubeClip: a streamline object's clip planes, the part of a ray they keep, and where a plane
// cuts a tube (the cut is capped: a flat fragment on the plane).
#pragma once
#include <cstdint>
#include <vector>

#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

#include "core/ray.hpp"
#include "intermix/scene.hpp"
#include "tubes/tube_geometry.hpp"

namespace imx {

class TubeClip {
 public:
  // The part of a ray in [0, inf) that every plane keeps: lo < t < hi, with the plane that sets
  // each end (-1: the ray's start, or no end).
  struct Span {
    float lo = 0.0f, hi = 0.0f;
    int lo_plane = -1, hi_plane = -1;
  };

  // `object`'s clip_planes over the tubes `geometry` built for it.
  TubeClip(const StreamlineObject& object, const TubeGeometry& geometry);

  Span kept(const Ray& ray) const;

  // Whether `p`, a point of plane `plane`, lies inside a tube (within the radius of a segment
  // crossing the plane); if so *at holds the nearest segment and where along it, for colour.
  bool inside(int plane, const glm::vec3& p, TubeHit* at) const;

  // The plane's unit normal, toward the side it keeps.
  const glm::vec3& normal(int plane) const { return planes_[plane].normal; }
  size_t plane_count() const { return planes_.size(); }
  // Segments listed as crossing some plane (what a cap test looks at), for tests and reports.
  size_t crossing_segments() const;

 private:
  // One plane and a grid, in the plane's own coordinates, of the segments whose tubes cross it.
  struct Plane {
    glm::vec3 point{0.0f}, normal{0.0f}, e1{0.0f}, e2{0.0f};
    glm::vec2 low{0.0f};  // the grid's corner in (e1, e2) coordinates
    float cell = 1.0f;    // mm
    int nx = 0, ny = 0;
    std::vector<uint32_t> cell_start;  // cell c owns items[cell_start[c] .. cell_start[c + 1])
    std::vector<uint32_t> items;       // segment indices
    size_t segments = 0;
  };
  void build(Plane& plane) const;

  const Streamlines* streamlines_ = nullptr;
  const TubeGeometry* geometry_ = nullptr;
  float radius_ = 0.0f;
  std::vector<Plane> planes_;
};

}  // namespace imx
