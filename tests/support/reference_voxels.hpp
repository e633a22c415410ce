// A reference reader's voxels (numpy's little-endian float64, C order, written by a test's
// Python script) and the check that a volume holds exactly them.
#pragma once
#include <algorithm>
#include <cfloat>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "intermix/volume.hpp"
#include "temp_dir.hpp"

namespace imx::test {

// The float64 values of `file`.
inline std::vector<double> read_reference_values(const std::filesystem::path& file) {
  const std::string bytes = read_bytes(file);
  std::vector<double> values(bytes.size() / sizeof(double));
  std::memcpy(values.data(), bytes.data(), values.size() * sizeof(double));
  return values;
}

// Every voxel of `v` equals `reader`'s value in `ref_file`, as the storage type holds it: f32
// for wide types, doubles beyond float's range its largest (raw_voxels.hpp), NaN as NaN.
inline void expect_reference_voxels(const VolumeData& v, const std::filesystem::path& ref_file,
                                    const char* reader) {
  const std::vector<double> ref = read_reference_values(ref_file);
  ASSERT_EQ(ref.size(), v.voxel_count()) << ref_file;
  size_t n = 0, wrong = 0;
  for (int k = 0; k < v.dims.z; ++k)
    for (int j = 0; j < v.dims.y; ++j)
      for (int i = 0; i < v.dims.x; ++i, ++n) {
        double want = ref[n];
        if (v.type() == VoxelType::f32 && std::isfinite(want))
          want = static_cast<float>(std::clamp(want, -double{FLT_MAX}, double{FLT_MAX}));
        const double got = v.value_at(i, j, k);
        const bool same = std::isnan(want) ? std::isnan(got) : got == want;
        if (!same && wrong++ < 5)
          ADD_FAILURE() << ref_file << " voxel " << i << "," << j << "," << k << ": " << got << ", "
                        << reader << " reads " << want;
      }
  EXPECT_EQ(wrong, 0u) << ref_file;
}

}  // namespace imx::test
