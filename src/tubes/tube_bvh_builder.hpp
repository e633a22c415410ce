// The binned-SAH builder of TubeBvh's binary tree: runs' boxes in, nodes out, records
// partitioned in place and subtrees built in parallel.
#pragma once
#include <cstdint>
#include <limits>
#include <vector>

#include <glm/glm.hpp>

#include "tubes/tube_bvh.hpp"

namespace imx {

// The deepest a TubeBvh's binary tree gets, so that traversal stacks are fixed arrays.
inline constexpr int kTubeBvhMaxDepth = 128;  // the builder's median depth + log2 of 2^32 runs

// Trivial, so that the builder's bin arrays cost nothing until used: start from empty().
struct TubeBox {
  glm::vec3 low, high;
  static TubeBox empty() {
    return {glm::vec3(std::numeric_limits<float>::max()),
            glm::vec3(-std::numeric_limits<float>::max())};
  }
  void grow(const TubeBox& b) { low = glm::min(low, b.low), high = glm::max(high, b.high); }
  void grow(const glm::vec3& p) { low = glm::min(low, p), high = glm::max(high, p); }
  float half_area() const {
    const glm::vec3 e = glm::max(high - low, glm::vec3(0.0f));
    return e.x * e.y + e.y * e.z + e.z * e.x;
  }
};

// A run's box and index: the builder partitions these records themselves, so that each
// level reads them in order.
struct TubeBvhItem {
  TubeBox box;
  uint32_t run;
  glm::vec3 centre() const { return 0.5f * box.low + 0.5f * box.high; }  // no overflow
};

// The binary tree over `items` (reordered: a leaf's runs are consecutive), whose union box is
// `bounds`: node 0 the root, an inner node's children at `first` and `first` + 1, a leaf of at
// most 2 runs. At most kTubeBvhMaxDepth deep.
std::vector<TubeBvh::Node> build_tube_tree(std::vector<TubeBvhItem>& items, const TubeBox& bounds);

}  // namespace imx
