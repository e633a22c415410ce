// Uncompressed voxels in this machine's byte order are viewed in place (mapped), others read:
// either way the values are the file's, and a view never writes back to the file.
#include <gtest/gtest.h>

#include <cstdint>
#include <filesystem>
#include <variant>

#include "intermix/io.hpp"
#include "io/voxels/mapped_voxels.hpp"
#include "pattern_volume.hpp"
#include "temp_dir.hpp"
#include "volume_bytes.hpp"

namespace imx {
namespace {

template <class T>
const VoxelBuffer<T>& buffer_of(const VolumeData& v) {
  return std::get<VoxelBuffer<T>>(v.voxels);
}

// The writers' NRRD (its header padded to 64 bytes) and NIfTI (voxels at 352), and a detached
// MetaImage (voxels at 0 of their own file) map; an .mha's voxels follow a header of any length,
// so it maps when that length suits the type.
TEST(MappedVoxels, UncompressedNrrdNiftiAndMetaImageAreViewedWithTheirValues) {
  test::TempDir dir;
  const VolumeData original = test::pattern_volume<int16_t>({23, 17, 9});
  for (const char* name : {"v.nrrd", "v.nii"}) {
    write_volume(original, dir / name, /*compress=*/false);
    const VolumeData read = read_volume(dir / name);
    EXPECT_FALSE(buffer_of<int16_t>(read).owns()) << name << ": copied, not mapped";
    EXPECT_EQ(buffer_of<int16_t>(read), buffer_of<int16_t>(original)) << name;
  }
  test::write_bytes(dir / "v.mhd",
                    "ObjectType = Image\nNDims = 3\nDimSize = 23 17 9\nElementType = MET_SHORT\n"
                    "BinaryDataByteOrderMSB = False\nElementDataFile = v.raw\n");
  const auto& values = buffer_of<int16_t>(original);
  test::write_bytes(dir / "v.raw",
                    test::raw_bytes(std::vector<int16_t>(values.begin(), values.end())));
  const VolumeData detached = read_volume(dir / "v.mhd");
  EXPECT_FALSE(buffer_of<int16_t>(detached).owns());
  EXPECT_EQ(buffer_of<int16_t>(detached), values);
  write_volume(original, dir / "v.mha", false);
  EXPECT_EQ(buffer_of<int16_t>(read_volume(dir / "v.mha")), values);
}

TEST(MappedVoxels, CompressedFilesAndRegionsAreRead) {
  test::TempDir dir;
  const VolumeData original = test::pattern_volume<uint16_t>({12, 10, 6});
  for (const char* name : {"c.nrrd", "c.nii.gz", "c.mha"}) {
    write_volume(original, dir / name, /*compress=*/true);
    const VolumeData read = read_volume(dir / name);
    EXPECT_TRUE(buffer_of<uint16_t>(read).owns()) << name;
    EXPECT_EQ(buffer_of<uint16_t>(read), buffer_of<uint16_t>(original)) << name;
  }
  write_volume(original, dir / "r.nrrd", false);
  const VolumeData part = read_volume_region(dir / "r.nrrd", {{1, 2, 3}, {5, 6, 6}});
  EXPECT_TRUE(buffer_of<uint16_t>(part).owns());
  EXPECT_EQ(buffer_of<uint16_t>(part)[0], buffer_of<uint16_t>(original)[(3 * 10 + 2) * 12 + 1]);
}

TEST(MappedVoxels, AMappingNeedsAnAlignedNativeRunThatTheFileHolds) {
  test::TempDir dir;
  const std::vector<float> values = {1.5f, -2.0f, 3.25f, 4.0f};
  test::write_bytes(dir / "f.raw", "1234" + test::raw_bytes(values));
  const auto mapped = detail::map_voxels(dir / "f.raw", 4, detail::RawType::f32, values.size());
  ASSERT_TRUE(mapped);
  const auto& view = std::get<VoxelBuffer<float>>(*mapped);
  EXPECT_EQ(std::vector<float>(view.begin(), view.end()), values);
  EXPECT_FALSE(
      detail::map_voxels(dir / "f.raw", 2, detail::RawType::f32, 4));  // not aligned to a float
  EXPECT_FALSE(detail::map_voxels(dir / "f.raw", 4, detail::RawType::f32, 5));  // past the end
  EXPECT_FALSE(detail::map_voxels(dir / "f.raw", 0, detail::RawType::f64, 2));  // stored converted
  EXPECT_FALSE(detail::map_voxels(dir / "none.raw", 0, detail::RawType::u8, 1));  // no file
  // Changing the view's copy leaves the file as it was.
  VolumeData v;
  v.dims = {4, 1, 1};
  v.voxels = std::get<VoxelBuffer<float>>(*mapped);
  std::get<VoxelBuffer<float>>(v.voxels).mutable_data()[0] = 99.0f;
  EXPECT_EQ(test::read_bytes(dir / "f.raw"), "1234" + test::raw_bytes(values));
}

}  // namespace
}  // namespace imx
