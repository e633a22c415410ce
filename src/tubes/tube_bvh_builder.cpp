#include "tubes/tube_bvh_builder.hpp"

#include <algorithm>
#include <array>
#include <atomic>
#include <cmath>

#include <tbb/parallel_invoke.h>

namespace imx {
namespace {

constexpr int kBins = 32;
constexpr int kMaxLeafRuns = 2;   // at most 4: a leaf child keeps its count in 2 bits
constexpr float kRunCost = 2.0f;  // a run's test against a box visit's
constexpr int kMedianDepth = 48;  // deeper than this, splits halve: depth stays bounded
constexpr size_t kParallelRuns = 4096;

using Box = TubeBox;
using Item = TubeBvhItem;

class Builder {
 public:
  Builder(std::vector<Item>& items, std::vector<TubeBvh::Node>& nodes)
      : items_(items), nodes_(nodes) {}

  void build(uint32_t node, uint32_t begin, uint32_t end, const Box& bounds, int depth) {
    TubeBvh::Node& n = nodes_[node];
    for (int a = 0; a < 3; ++a) n.low[a] = bounds.low[a], n.high[a] = bounds.high[a];
    const uint32_t count = end - begin;
    if (count <= 1) return leaf(n, begin, count);
    Box centroids = Box::empty();
    for (uint32_t i = begin; i < end; ++i) centroids.grow(items_[i].centre());
    const glm::vec3 extent = centroids.high - centroids.low;
    const int axis =
        extent.x >= extent.y && extent.x >= extent.z ? 0 : (extent.y >= extent.z ? 1 : 2);
    uint32_t middle = begin;
    Box left = Box::empty(), right = Box::empty();
    if (extent[axis] > 0.0f && depth < kMedianDepth) {
      const Split s = best_split(begin, end, centroids, bounds);
      if (s.axis >= 0 && count <= kMaxLeafRuns && s.cost >= kRunCost * static_cast<float>(count))
        return leaf(n, begin, count);
      if (s.axis >= 0) {
        const float scale = s.bins / extent[s.axis], low = centroids.low[s.axis];
        const auto* it =
            std::partition(items_.data() + begin, items_.data() + end, [&](const Item& item) {
              return bin(item.centre()[s.axis], low, scale, s.bins) < s.bin;
            });
        middle = static_cast<uint32_t>(it - items_.data());
        left = s.left, right = s.right;
      }
    }
    if (middle == begin || middle == end) {  // no useful split: halve by position
      if (count <= kMaxLeafRuns) return leaf(n, begin, count);
      middle = begin + count / 2;
      std::nth_element(
          items_.data() + begin, items_.data() + middle, items_.data() + end,
          [&](const Item& x, const Item& y) { return x.centre()[axis] < y.centre()[axis]; });
      left = right = Box::empty();
      for (uint32_t i = begin; i < middle; ++i) left.grow(items_[i].box);
      for (uint32_t i = middle; i < end; ++i) right.grow(items_[i].box);
    }
    const uint32_t child = next_.fetch_add(2);
    n.first = child;
    n.count = 0;
    auto build_left = [&] { build(child, begin, middle, left, depth + 1); };
    auto build_right = [&] { build(child + 1, middle, end, right, depth + 1); };
    if (count > kParallelRuns) {
      tbb::parallel_invoke(build_left, build_right);
    } else {
      build_left();
      build_right();
    }
  }

  uint32_t used() const { return next_.load(); }

 private:
  struct Split {
    int axis = -1, bin = 0, bins = kBins;
    float cost = std::numeric_limits<float>::max();  // in units of one run's test over the node
    Box left, right;
  };

  static int bin(float c, float low, float scale, int bins) {
    const float x = (c - low) * scale;  // NaN- and overflow-safe: a huge box's centre is finite
    return x >= 1.0f ? std::min(static_cast<int>(std::min(x, 1e9f)), bins - 1) : 0;
  }
  static void leaf(TubeBvh::Node& n, uint32_t begin, uint32_t count) {
    n.first = begin;
    n.count = count;
  }

  // The surface area heuristic over bins of the centroids on each axis (kBins, fewer for small
  // nodes, where the bins' own cost would dominate); a box visit costs kRunCost runs' tests.
  Split best_split(uint32_t begin, uint32_t end, const Box& centroids, const Box& bounds) const {
    Split best;
    const float node_area = std::max(bounds.half_area(), 1e-12f);
    const int bins = std::clamp(static_cast<int>(end - begin), 4, kBins);
    for (int axis = 0; axis < 3; ++axis) {
      const float extent = centroids.high[axis] - centroids.low[axis];
      if (!(extent > 0.0f)) continue;
      const float scale = bins / extent, low = centroids.low[axis];
      std::array<Box, kBins> bin_box;
      std::array<uint32_t, kBins> counts;
      for (int b = 0; b < bins; ++b) bin_box[b] = Box::empty(), counts[b] = 0;
      for (uint32_t i = begin; i < end; ++i) {
        const int b = bin(items_[i].centre()[axis], low, scale, bins);
        bin_box[b].grow(items_[i].box);
        ++counts[b];
      }
      std::array<float, kBins> right_cost;
      std::array<Box, kBins> right_box;
      Box acc = Box::empty();
      uint32_t n = 0;
      for (int b = bins - 1; b > 0; --b) {
        acc.grow(bin_box[b]);
        n += counts[b];
        right_box[b] = acc;
        right_cost[b] = n * acc.half_area();
      }
      acc = Box::empty();
      n = 0;
      for (int b = 1; b < bins; ++b) {
        acc.grow(bin_box[b - 1]);
        n += counts[b - 1];
        if (n == 0 || n == end - begin) continue;
        const float cost = 1.0f + kRunCost * (n * acc.half_area() + right_cost[b]) / node_area;
        if (cost < best.cost) best = Split{axis, b, bins, cost, acc, right_box[b]};
      }
    }
    return best;
  }

  std::vector<Item>& items_;
  std::vector<TubeBvh::Node>& nodes_;
  std::atomic<uint32_t> next_{2};  // children in pairs at even indices: one cache line
};

}  // namespace

std::vector<TubeBvh::Node> build_tube_tree(std::vector<TubeBvhItem>& items, const TubeBox& bounds) {
  std::vector<TubeBvh::Node> binary(2 * items.size() + 2);
  Builder builder(items, binary);
  builder.build(0, 0, static_cast<uint32_t>(items.size()), bounds, 0);
  binary.resize(builder.used());
  return binary;
}

}  // namespace imx
