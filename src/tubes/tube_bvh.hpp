// TubeBvh: exact ray crossings with round tubes (capsules around polyline segments, joined
// without inner surfaces), through a bounding volume hierarchy over short runs of segments.
#pragma once
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include <glm/vec3.hpp>

#include "core/ray.hpp"

namespace imx {

// One crossing of a ray with a tube's surface.
struct TubeHit {
  float t = 0.0f;          // along the ray, mm
  glm::vec3 normal{0.0f};  // the surface's geometric normal, not unit length
  uint32_t segment = 0;    // the segment's index in TubeBvh::Input::segment_points
  float u = 0.0f;          // where along the segment, 0 at its first point, 1 at its second
};

// The run of joined segments a crossing was found in, as the hierarchy keeps it at hand:
// points[0..segments] are its segments' points, points[-1] the one before (or points[0] again
// where the tube begins; joins bit 0 says which) and points[segments + 1] the one after (bit 1).
struct TubeRunPoints {
  const glm::vec3* points;
  uint32_t first_segment;
  uint16_t segments, joins;
};

// The K nearest crossings found so far, sorted; once full, the farthest bounds the search.
struct TubeHitList {
  TubeHit* hits;
  size_t capacity;
  size_t count = 0;
  float t_min, t_max;
  float reach() const { return count == capacity ? hits[capacity - 1].t : t_max; }
  void add(const TubeHit& hit, const TubeRunPoints&) {
    if (!(hit.t > t_min) || !(hit.t < reach())) return;
    size_t i = count < capacity ? count++ : capacity - 1;
    for (; i > 0 && hits[i - 1].t > hit.t; --i) hits[i] = hits[i - 1];
    hits[i] = hit;
  }
};

// Receives a ray's crossings in no particular order (TubeBvh::visit_hits): those with
// t_min < t < reach, where `reach` may fall as they come, so that nothing behind it is looked for.
class TubeHitVisitor {
 public:
  float t_min = 0.0f, reach = INFINITY;
  virtual void add(const TubeHit& hit, const TubeRunPoints& run) = 0;

 protected:
  ~TubeHitVisitor() = default;
};

class TubeBvh {
 public:
  struct Input {
    // The points and, per segment, the index of its first point (the second follows it).
    // Segments whose first points follow each other share a point and are joined: the tube
    // around them is one surface. Both spans must outlive the BVH.
    std::span<const glm::vec3> points;
    std::span<const uint32_t> segment_points;
    float radius = 0.5f;           // mm, of every segment unless `radii` is given
    std::span<const float> radii;  // mm per segment, or empty; must outlive the BVH
  };

  TubeBvh() = default;
  // Builds in parallel. Throws std::length_error when the runs' points need kMaxStream slots
  // or more (TubeGeometry refuses such objects first), else std::bad_alloc only.
  explicit TubeBvh(const Input& input);

  // The crossings of `ray` (unit direction) with t_min < t < t_max, nearest first: the
  // out.size() nearest of them. Returns how many were found. Pure and thread-safe.
  size_t nearest_hits(const Ray& ray, float t_min, float t_max, std::span<TubeHit> out) const;
  // Hands `visitor` the crossings of `ray` it still wants, nearest boxes first. Thread-safe.
  void visit_hits(const Ray& ray, TubeHitVisitor& visitor) const;

  // Whether `point` lies within a segment's radius of its axis; if so and `where` is given,
  // a hit naming the nearest such segment, with the normal from its axis to the point, t = 0.
  bool contains(const glm::vec3& point, TubeHit* where = nullptr) const;

  // Resident bytes of the hierarchy (the points and segment indices are the caller's).
  size_t bytes() const;

  // A node of the binary tree the builder makes: its box, and either two children (count 0: at
  // `first`, `first` + 1) or `count` runs from `first` on.
  struct Node {
    float low[3];
    uint32_t first;
    float high[3];
    uint32_t count;
  };
  // Up to kRunSegments consecutive segments of one tube; `joins` says whether the tube goes on
  // before the first (bit 0) and after the last (bit 1).
  struct Run {
    uint32_t first_segment;
    uint16_t segments;
    uint16_t joins;
    float bound = 0.0f;  // every capsule lies within this of the chord first-to-last point
  };
  static constexpr int kRunSegments = 8;

  // A node of the traversed tree: up to 8 children's boxes, tested at once. A child is
  // kNoChild, a node index, or kLeafChild | (runs - 1) << 29 | its first run's stream offset.
  struct alignas(32) WideNode {
    float low[3][8];
    float high[3][8];
    uint32_t child[8];
  };
  static constexpr uint32_t kNoChild = ~0u;
  static constexpr uint32_t kLeafChild = 1u << 31;
  // A leaf child keeps its stream offset in 29 bits: the slots of all runs, kRunExtra + their
  // segments each, stay below this.
  static constexpr uint64_t kMaxStream = uint64_t{1} << 29;
  static constexpr uint32_t kRunExtra = 4;  // slots of a run besides its segments

 private:
  // The leaves' runs in hierarchy order, each as its Run, the point before it (or its first
  // again), its segments + 1 points and the point after it (or its last again): a leaf reads
  // one stretch of memory. A leaf node's `first` is its first run's offset here.
  // Adds the crossings of `ray` with the run at `run` to `sink` (a TubeHitList or a visitor);
  // returns the run's slots.
  template <class Sink>
  uint32_t hit_run(const glm::vec3* run, const Ray& ray, Sink& sink) const;
  // The boxes `ray` enters, nearest first, while `sink` still wants what lies in them.
  template <class Sink>
  void traverse(const Ray& ray, Sink& sink) const;
  Input input_;
  uint32_t collapse(const std::vector<Node>& binary, uint32_t node);
  static void set_child(WideNode& w, int i, const Node* n, uint32_t inner);
  std::vector<WideNode> nodes_;
  std::vector<glm::vec3> stream_;
};

}  // namespace imx
