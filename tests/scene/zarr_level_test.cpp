// An OME-Zarr pyramid's levels in scenes: "level" K or "auto" (the finest that can be held),
// the viewer's coarse levels for a scene from files, and the type of the error a volume too
// large to hold gives (a render then goes on in bricks).
#include <gtest/gtest.h>

#include <string>

#include "intermix/error.hpp"
#include "intermix/io.hpp"
#include "intermix/limits.hpp"
#include "io/zarr/ome_zarr_writer.hpp"
#include "scene/scene_from_files.hpp"
#include "temp_dir.hpp"

namespace imx {
namespace {

// Input limits of `bytes` for the life of the object.
class Budget {
 public:
  explicit Budget(uint64_t bytes) : saved_(input_limits()) {
    set_input_limits({bytes, saved_.allow_external_data});
  }
  ~Budget() { set_input_limits(saved_); }

 private:
  InputLimits saved_;
};

// A 64-voxel phantom (about 50x64x45 int16, 280 KiB) as a pyramid of 16^3 chunks.
std::filesystem::path write_pyramid(const test::TempDir& dir) {
  const VolumeData v = make_phantom("ct-head", 64);
  const VolumeHeader h{v.dims, v.type(), v.index_to_world, 1, {}};
  const std::filesystem::path out = dir / "head.zarr";
  detail::OmeZarrWriteOptions options;
  options.chunk = 16;
  detail::write_ome_zarr(h, [&](const VoxelBox& b) { return crop(v, b, "phantom"); }, out,
                         options);
  return out;
}

std::string scene_with_level(const std::filesystem::path& zarr, const std::string& level) {
  return R"({"camera": {"eye": [0, -500, 0]}, "objects": [{"name": "h", "type": "volume",
      "transfer_function": {"preset": "ct-bone"},
      "source": {"file": ")" +
         zarr.string() + R"(", "level": )" + level + "}}]}";
}

TEST(ZarrLevels, ALevelIsReadByNumberOrAsTheFinestThatFits) {
  test::TempDir dir;
  const std::filesystem::path zarr = write_pyramid(dir);
  const glm::ivec3 full = read_volume_header(zarr).dims;
  const glm::ivec3 half = (full + 1) / 2;
  EXPECT_EQ(parse_scene(scene_with_level(zarr, "1"), ".", "s").volumes[0].data->dims, half);
  EXPECT_EQ(parse_scene(scene_with_level(zarr, "\"auto\""), ".", "s").volumes[0].data->dims, full);
  {
    // Half the budget below level 0's bytes, above level 1's.
    const Budget budget(static_cast<uint64_t>(full.x) * full.y * full.z * 2);
    EXPECT_THROW(parse_scene(scene_with_level(zarr, "0"), ".", "s"), VolumeTooLarge);
    const Scene s = parse_scene(scene_with_level(zarr, "\"auto\""), ".", "s");
    EXPECT_EQ(s.volumes[0].data->dims, half);
    bool noted = false;
    for (const std::string& n : s.notes) noted |= n.find("level 1 of") != std::string::npos;
    EXPECT_TRUE(noted);
    // The viewer's scene from files takes that level; render's stays at level 0.
    EXPECT_EQ(scene_from_files({zarr}, "anterior", {}, {}, true).scene().volumes[0].data->dims,
              half);
    EXPECT_THROW(scene_from_files({zarr}), VolumeTooLarge);
  }
  try {
    parse_scene(scene_with_level(zarr, "9"), ".", "s");
    FAIL() << "accepted level 9";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("source.level: level 9 requested: head.zarr has"),
              std::string::npos)
        << e.what();
  }
}

}  // namespace
}  // namespace imx
