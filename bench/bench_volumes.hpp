// Synthetic volumes for the micro-benchmarks: quick to make, with empty and busy regions.
#pragma once
#include <cmath>
#include <memory>
#include <vector>

#include "intermix/volume.hpp"

namespace imx::bench {

// A shell between radii 0.25 and 0.45 of the grid (values rising to 255 at 0.35) plus a ripple,
// in the range [0, 255] mapped to T by scale and offset: the centre and corners are empty.
template <class T>
std::shared_ptr<const VolumeData> shell_volume(int n, float scale = 1.0f, float offset = 0.0f) {
  std::vector<T> data(static_cast<size_t>(n) * n * n);
  size_t idx = 0;
  for (int k = 0; k < n; ++k)
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < n; ++i) {
        float x = (i + 0.5f) / n - 0.5f, y = (j + 0.5f) / n - 0.5f, z = (k + 0.5f) / n - 0.5f;
        float r = std::sqrt(x * x + y * y + z * z);
        float v = std::max(0.0f, 1.0f - std::abs(r - 0.35f) / 0.1f) * 255.0f;
        v *= 0.8f + 0.2f * std::sin(40.0f * x) * std::sin(40.0f * y);
        data[idx++] = static_cast<T>(v * scale + offset);
      }
  auto vol = std::make_shared<VolumeData>();
  vol->dims = glm::ivec3(n);
  vol->voxels = std::move(data);
  return vol;
}

}  // namespace imx::bench
