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

// Calls fn(value) for the finite voxels of a regular subsample of `data` (every stride-th voxel
// along each axis) of at most about `max_samples` voxels: every voxel of a small volume.
template <class Fn>
void for_each_sampled_value(const VolumeData& data, double max_samples, Fn&& fn) {
  const double voxels = static_cast<double>(data.voxel_count());
  const size_t stride =
      voxels > max_samples ? static_cast<size_t>(std::ceil(std::cbrt(voxels / max_samples))) : 1;
  const size_t nx = static_cast<size_t>(std::max(data.dims.x, 0));
  const size_t ny = static_cast<size_t>(std::max(data.dims.y, 0));
  const size_t nz = static_cast<size_t>(std::max(data.dims.z, 0));
  std::visit(
      [&](const auto& v) {
        if (v.size() < nx * ny * nz) return;  // inconsistent data: validate() refuses it
        for (size_t z = 0; z < nz; z += stride)
          for (size_t y = 0; y < ny; y += stride) {
            const auto* row = v.data() + (z * ny + y) * nx;
            for (size_t x = 0; x < nx; x += stride)
              if (const double s = static_cast<double>(row[x]); std::isfinite(s)) fn(s);
          }
      },
      data.voxels);
}

// The values below which each of `fractions` (in [0, 1]) of the finite voxels lie, from a
// subsample of at most about a million voxels; empty when the volume has no finite voxel. When
// at least half the voxels hold the smallest value (a background of zeros around an MR head, a
// sparse map), those are left out: the fractions are of the voxels above the background.
std::vector<double> value_percentiles(const VolumeData& data, std::span<const double> fractions);

}  // namespace imx
