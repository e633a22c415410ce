#include <cmath>
#include <limits>
#include <string>

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

TEST(VolumeData, NonFiniteVoxelsAreRefusedWithTheirIndex) {
  VolumeData v;
  v.dims = {4, 3, 2};
  std::vector<float> voxels(24, 1.0f);
  voxels[1 + 4 * 2 + 12 * 1] = std::numeric_limits<float>::quiet_NaN();  // voxel (1, 2, 1)
  voxels[23] = std::numeric_limits<float>::infinity();
  v.voxels = voxels;
  std::string message = validation_error(v);
  EXPECT_NE(message.find("scan.mha"), std::string::npos) << message;
  EXPECT_NE(message.find("voxel (1, 2, 1) is nan"), std::string::npos) << message;
  EXPECT_NE(message.find("2 non-finite"), std::string::npos) << message;

  voxels[1 + 4 * 2 + 12 * 1] = std::numeric_limits<float>::max();
  voxels[23] = -std::numeric_limits<float>::max();
  v.voxels = voxels;
  EXPECT_EQ(validation_error(v), "") << "finite extremes are valid voxels";
}

}  // namespace
}  // namespace imx
