#include "io/mesh/vertex_weld.hpp"

#include <algorithm>
#include <array>
#include <bit>
#include <cstddef>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_sort.h>

namespace imx::detail {
namespace {

uint32_t bits(float f) {
  return std::bit_cast<uint32_t>(f + 0.0f);  // +0 first: -0 and +0 weld
}

// A vertex's bits and its input index: sorting puts equal vertices together, first one first.
template <size_t N>
struct Keyed {
  std::array<uint32_t, N> bits;
  uint32_t index;
  // Word by word: std::array's own comparisons call memcmp, which dominated the sort.
  bool same_bits(const Keyed& o) const {
    for (size_t i = 0; i < N; ++i)
      if (bits[i] != o.bits[i]) return false;
    return true;
  }
  bool operator<(const Keyed& o) const {
    for (size_t i = 0; i < N; ++i)
      if (bits[i] != o.bits[i]) return bits[i] < o.bits[i];
    return index < o.index;
  }
};

template <size_t N>
Weld weld(std::span<const glm::vec3> positions, std::span<const glm::vec3> colors) {
  const size_t n = positions.size();
  Weld out;
  out.id.resize(n);
  {
    std::vector<Keyed<N>> keys(n);
    tbb::parallel_for(tbb::blocked_range<size_t>(0, n), [&](const auto& r) {
      for (size_t i = r.begin(); i != r.end(); ++i) {
        Keyed<N>& k = keys[i];
        for (int c = 0; c < 3; ++c) k.bits[c] = bits(positions[i][c]);
        if constexpr (N == 6)
          for (int c = 0; c < 3; ++c) k.bits[3 + c] = bits(colors[i][c]);
        k.index = static_cast<uint32_t>(i);
      }
    });
    tbb::parallel_sort(keys.begin(), keys.end());
    // Each vertex points at the first (lowest) input vertex of its run of equal bits.
    tbb::parallel_for(tbb::blocked_range<size_t>(0, n), [&](const auto& r) {
      size_t run = r.begin();
      while (run > 0 && keys[run - 1].same_bits(keys[r.begin()])) --run;
      for (size_t j = r.begin(); j != r.end(); ++j) {
        if (!keys[j].same_bits(keys[run])) run = j;
        out.id[keys[j].index] = keys[run].index;
      }
    });
  }
  size_t welded = 0;
  for (size_t i = 0; i < n; ++i) welded += out.id[i] == i ? 1 : 0;
  out.first.reserve(welded);
  // Numbered in input order: a vertex's first comes before it, so its number is already set.
  for (size_t i = 0; i < n; ++i) {
    if (out.id[i] == i) {
      out.id[i] = static_cast<uint32_t>(out.first.size());
      out.first.push_back(static_cast<uint32_t>(i));
    } else {
      out.id[i] = out.id[out.id[i]];
    }
  }
  return out;
}

}  // namespace

Weld weld_vertices(std::span<const glm::vec3> positions, std::span<const glm::vec3> colors) {
  return colors.size() == positions.size() && !colors.empty() ? weld<6>(positions, colors)
                                                              : weld<3>(positions, colors);
}

}  // namespace imx::detail
