// A float32 file of whole numbers is held as int16 by the scene, with a note; others stay float.
#include <gtest/gtest.h>

#include <algorithm>

#include "intermix/io.hpp"
#include "intermix/scene.hpp"
#include "scene_fixture.hpp"
#include "temp_dir.hpp"

namespace imx {
namespace {

Scene scene_of(const std::filesystem::path& file) {
  return parse_scene(R"({"objects": [{"name": "ct", "type": "volume", "source": {"file": ")" +
                         file.string() + R"("}}]})",
                     file.parent_path(), "scene.json");
}

std::filesystem::path write_floats(const test::TempDir& dir, const std::string& name,
                                   float offset) {
  VolumeData v;
  v.dims = {8, 6, 4};
  std::vector<float> values;
  for (int i = 0; i < 8 * 6 * 4; ++i) values.push_back(static_cast<float>(i * 13 - 1000) + offset);
  v.voxels = VoxelBuffer<float>(std::move(values));
  const std::filesystem::path file = dir / name;
  write_volume(v, file);
  return file;
}

TEST(CompactVolumeScene, WholeNumberFloatsAreHeldAsInt16WithANote) {
  test::TempDir dir;
  const Scene whole = scene_of(write_floats(dir, "whole.nii", 0.0f));
  ASSERT_EQ(whole.volumes.size(), 1u);
  EXPECT_EQ(whole.volumes[0].data->type(), VoxelType::i16);
  EXPECT_EQ(whole.volumes[0].data->value_at(3, 2, 1), (3 + 8 * 2 + 48 * 1) * 13 - 1000);
  EXPECT_TRUE(std::any_of(whole.notes.begin(), whole.notes.end(), [](const std::string& n) {
    return n.find("whole numbers: held as int16") != std::string::npos;
  }));
  const Scene fraction = scene_of(write_floats(dir, "fraction.nii", 0.5f));
  EXPECT_EQ(fraction.volumes[0].data->type(), VoxelType::f32);
  EXPECT_EQ(fraction.volumes[0].data->value_at(3, 2, 1), (3 + 8 * 2 + 48 * 1) * 13 - 1000 + 0.5);
}

}  // namespace
}  // namespace imx
