// Stratified sample positions inside a pixel: an n x n grid of stratum centres.
#pragma once
#include <cmath>
#include <vector>

#include <fmt/format.h>
#include <glm/vec2.hpp>

#include "intermix/error.hpp"

namespace imx {

// Offsets in [0,1)^2 for `spp` samples per pixel; spp must be a perfect square.
inline std::vector<glm::vec2> stratified_offsets(int spp) {
  int n = static_cast<int>(std::lround(std::sqrt(static_cast<double>(spp))));
  if (spp < 1 || n * n != spp)
    throw Error(fmt::format("spp: {} is not a perfect square (1, 4, 9, 16, ...)", spp));
  std::vector<glm::vec2> offsets;
  offsets.reserve(spp);
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i)
      offsets.emplace_back((static_cast<float>(i) + 0.5f) / n, (static_cast<float>(j) + 0.5f) / n);
  return offsets;
}

// The offsets a frame samples: the whole pattern, or only entry `sample_index` of it (>= 0).
inline std::vector<glm::vec2> frame_offsets(int spp, int sample_index) {
  std::vector<glm::vec2> offsets = stratified_offsets(spp);
  if (sample_index < 0) return offsets;
  if (sample_index >= spp)
    throw Error(fmt::format("sample_index: {} is outside the {}-sample pattern", sample_index, spp));
  return {offsets[static_cast<size_t>(sample_index)]};
}

}  // namespace imx
