// A regular subsample of a volume's finite values, for statistics that need not see every voxel
// (histograms, percentile ranges): bounded time and memory on any volume.
#pragma once
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <span>
#include <variant>
#include <vector>

#include "intermix/volume.hpp"

namespace imx {

// The step along each axis that leaves at most about `max_samples` of `data`'s voxels (1: all).
inline int sample_stride(const VolumeData& data, double max_samples) {
  const double voxels = static_cast<double>(data.voxel_count());
  return voxels > max_samples ? static_cast<int>(std::ceil(std::cbrt(voxels / max_samples))) : 1;
}

// Calls fn(i, j, k, value) for the finite voxels of a regular subsample of `data` (every
// sample_stride-th voxel along each axis): every voxel of a small volume.
template <class Fn>
void for_each_sampled_voxel(const VolumeData& data, double max_samples, Fn&& fn) {
  const int stride = sample_stride(data, max_samples);
  const int nx = std::max(data.dims.x, 0), ny = std::max(data.dims.y, 0),
            nz = std::max(data.dims.z, 0);
  std::visit(
      [&](const auto& v) {
        if (v.size() < data.voxel_count()) return;  // inconsistent data: validate() refuses it
        for (int z = 0; z < nz; z += stride)
          for (int y = 0; y < ny; y += stride) {
            const auto* row = v.data() + (static_cast<size_t>(z) * ny + y) * nx;
            for (int x = 0; x < nx; x += stride)
              if (const double s = static_cast<double>(row[x]); std::isfinite(s)) fn(x, y, z, s);
          }
      },
      data.voxels);
}

// The same, for statistics that need only the values.
template <class Fn>
void for_each_sampled_value(const VolumeData& data, double max_samples, Fn&& fn) {
  for_each_sampled_voxel(data, max_samples, [&](int, int, int, double s) { fn(s); });
}

// The values below which each of `fractions` (in [0, 1]) of the finite voxels lie, from a
// subsample of at most about a million voxels; empty when the volume has no finite voxel. When
// at least half the voxels hold the smallest value (a background of zeros around an MR head, a
// sparse map), those are left out: the fractions are of the voxels above the background.
std::vector<double> value_percentiles(const VolumeData& data, std::span<const double> fractions);

}  // namespace imx
