#include <algorithm>
#include <cmath>
#include <limits>
#include <string>
#include <utility>
#include <vector>

#include <gtest/gtest.h>

#include "intermix/error.hpp"
#include "intermix/volume.hpp"

namespace imx {
namespace {

std::string validation_error(const VolumeData& v) {
  try {
    v.validate("scan.mha");
  } catch (const Error& e) {
    return e.what();
  }
  return {};
}

// NaN and inf voxels are no data (a statistical map's outside of its mask), not an error: they
// are counted, and left out of the range.
TEST(VolumeData, NonFiniteVoxelsAreValidNoData) {
  VolumeData v;
  v.dims = {4, 3, 2};
  std::vector<float> voxels(24, 1.0f);
  voxels[1 + 4 * 2 + 12 * 1] = std::numeric_limits<float>::quiet_NaN();  // voxel (1, 2, 1)
  voxels[23] = std::numeric_limits<float>::infinity();
  voxels[0] = -std::numeric_limits<float>::infinity();
  voxels[5] = -3.0f;
  v.voxels = voxels;
  EXPECT_EQ(validation_error(v), "");
  EXPECT_EQ(non_finite_count(v), 3u);
  EXPECT_EQ(v.range(), std::make_pair(-3.0, 1.0));

  std::fill(voxels.begin(), voxels.end(), std::numeric_limits<float>::quiet_NaN());
  v.voxels = voxels;
  EXPECT_EQ(non_finite_count(v), 24u);
  EXPECT_EQ(v.range(), std::make_pair(0.0, 0.0)) << "no data at all";

  voxels[1 + 4 * 2 + 12 * 1] = std::numeric_limits<float>::max();
  voxels[23] = -std::numeric_limits<float>::max();
  v.voxels = voxels;
  EXPECT_EQ(validation_error(v), "") << "finite extremes are valid voxels";
  EXPECT_EQ(non_finite_count(v), 22u);

  VolumeData ints;
  ints.dims = {2, 1, 1};
  ints.voxels = std::vector<int16_t>{-5, 7};
  EXPECT_EQ(non_finite_count(ints), 0u);
  EXPECT_EQ(ints.range(), std::make_pair(-5.0, 7.0));
}

}  // namespace
}  // namespace imx
