// Whole-number float voxels become int16 or uint16 with every value kept; anything else stays.
#include "volume/compact_voxels.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

namespace imx {
namespace {

VolumeData floats(std::vector<float> values) {
  VolumeData v;
  v.dims = {static_cast<int>(values.size()), 1, 1};
  v.voxels = VoxelBuffer<float>(std::move(values));
  return v;
}

TEST(CompactVoxels, WholeNumbersInInt16RangeBecomeInt16WithTheSameValues) {
  std::vector<float> values;
  for (int i = -32768; i <= 32767; i += 7) values.push_back(static_cast<float>(i));
  values.push_back(-0.0f);
  values.push_back(32767.0f);
  const VolumeData v = floats(values);
  const std::optional<VoxelStorage> c = compact_integer_voxels(v);
  ASSERT_TRUE(c);
  const auto* ints = std::get_if<VoxelBuffer<int16_t>>(&*c);
  ASSERT_NE(ints, nullptr);
  ASSERT_EQ(ints->size(), values.size());
  for (size_t i = 0; i < values.size(); ++i)
    ASSERT_EQ(static_cast<float>(ints->data()[i]), values[i]);
}

TEST(CompactVoxels, AboveInt16ButWithinUint16BecomesUint16) {
  const std::optional<VoxelStorage> c = compact_integer_voxels(floats({0.0f, 40000.0f, 65535.0f}));
  ASSERT_TRUE(c);
  const auto* u = std::get_if<VoxelBuffer<uint16_t>>(&*c);
  ASSERT_NE(u, nullptr);
  EXPECT_EQ(u->data()[1], 40000);
  EXPECT_EQ(u->data()[2], 65535);
}

TEST(CompactVoxels, AnythingElseStaysFloat) {
  const float nan = std::numeric_limits<float>::quiet_NaN();
  const float inf = std::numeric_limits<float>::infinity();
  for (const std::vector<float>& values :
       std::vector<std::vector<float>>{{1.0f, 2.5f},        // a fraction
                                       {1.0f, nan},         // no data must stay no data
                                       {1.0f, inf},         // infinite
                                       {-1.0f, 40000.0f},   // neither range
                                       {70000.0f, 1.0f},    // above uint16
                                       {-40000.0f, 0.0f}})  // below int16
    EXPECT_FALSE(compact_integer_voxels(floats(values))) << values[0] << ", " << values[1];
  VolumeData ints;  // not float to begin with
  ints.dims = {2, 1, 1};
  ints.voxels = VoxelBuffer<int16_t>(std::vector<int16_t>{1, 2});
  EXPECT_FALSE(compact_integer_voxels(ints));
}

}  // namespace
}  // namespace imx
