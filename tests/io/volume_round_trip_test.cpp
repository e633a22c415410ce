// Every volume writer round-trips every voxel type: a volume whose voxels all differ, on an
// oblique affine with unequal spacings (pattern_volume), written as NRRD (raw, gzip), MetaImage
// (raw, zlib) and NIfTI (.nii, .nii.gz), reads back with its type, dims and voxels exactly and
// its index-to-world matrix to the format's precision, and the writer leaves no other file.
#include <filesystem>
#include <ostream>
#include <string>
#include <tuple>
#include <vector>

#include <gtest/gtest.h>

#include "intermix/io.hpp"
#include "pattern_volume.hpp"
#include "temp_dir.hpp"

namespace imx {
namespace {

using test::pattern_volume;
using Path = std::filesystem::path;

struct VolumeFormat {
  const char* name;  // in the test's name
  const char* file;
  void (*write)(const VolumeData&, const Path&);
  double affine_tolerance;
};

// NRRD prints the shortest decimals that round-trip, so its affine comes back exactly; MetaImage
// stores directions and spacings apart (a product's rounding); NIfTI stores floats.
const VolumeFormat kFormats[] = {
    {"NrrdRaw", "v.nrrd", [](const VolumeData& v, const Path& f) { write_nrrd(v, f, false); }, 0.0},
    {"NrrdGzip", "v.nrrd", [](const VolumeData& v, const Path& f) { write_nrrd(v, f, true); }, 0.0},
    {"MetaImageRaw", "v.mha",
     [](const VolumeData& v, const Path& f) { write_metaimage(v, f, false); }, 1e-12},
    {"MetaImageZlib", "v.mha",
     [](const VolumeData& v, const Path& f) { write_metaimage(v, f, true); }, 1e-12},
    {"Nifti", "v.nii", [](const VolumeData& v, const Path& f) { write_nifti(v, f, false); }, 1e-4},
    {"NiftiGz", "v.nii.gz", [](const VolumeData& v, const Path& f) { write_nifti(v, f, true); },
     1e-4},
};

const char* short_name(VoxelType type) {
  switch (type) {
    case VoxelType::u8:
      return "u8";
    case VoxelType::i16:
      return "i16";
    case VoxelType::u16:
      return "u16";
    case VoxelType::f32:
      return "f32";
  }
  return "?";
}

VolumeData pattern_of(VoxelType type, glm::ivec3 dims) {
  switch (type) {
    case VoxelType::u8:
      return pattern_volume<uint8_t>(dims);
    case VoxelType::i16:
      return pattern_volume<int16_t>(dims);
    case VoxelType::u16:
      return pattern_volume<uint16_t>(dims);
    case VoxelType::f32:
      return pattern_volume<float>(dims);
  }
  return {};
}

}  // namespace

// The voxel type in the parameters gtest prints.
static void PrintTo(VoxelType type, std::ostream* out) { *out << short_name(type); }

namespace {

class VolumeRoundTrip : public ::testing::TestWithParam<std::tuple<int, VoxelType>> {};

TEST_P(VolumeRoundTrip, KeepsTypeDimsVoxelsAndObliqueAffine) {
  const VolumeFormat& format = kFormats[std::get<0>(GetParam())];
  const VolumeData v = pattern_of(std::get<1>(GetParam()), {7, 5, 3});
  test::TempDir dir;
  format.write(v, dir / format.file);
  const VolumeData r = read_volume(dir / format.file);
  ASSERT_EQ(r.type(), v.type());
  ASSERT_EQ(r.dims, v.dims);
  int wrong = 0;
  for (int k = 0; k < v.dims.z; ++k)
    for (int j = 0; j < v.dims.y; ++j)
      for (int i = 0; i < v.dims.x; ++i)
        if (r.value_at(i, j, k) != v.value_at(i, j, k) && wrong++ < 5)
          ADD_FAILURE() << "voxel (" << i << "," << j << "," << k << ") reads "
                        << r.value_at(i, j, k) << ", was written " << v.value_at(i, j, k);
  EXPECT_EQ(wrong, 0) << "voxels that differ";
  EXPECT_TRUE(r.voxels == v.voxels);
  test::expect_same_affine(r.index_to_world, v.index_to_world, format.affine_tolerance);
  EXPECT_EQ(dir.entries(), std::vector<std::string>{format.file}) << "no temporary files remain";
}

INSTANTIATE_TEST_SUITE_P(Formats, VolumeRoundTrip,
                         ::testing::Combine(::testing::Range(0,
                                                             static_cast<int>(std::size(kFormats))),
                                            ::testing::Values(VoxelType::u8, VoxelType::i16,
                                                              VoxelType::u16, VoxelType::f32)),
                         [](const ::testing::TestParamInfo<VolumeRoundTrip::ParamType>& info) {
                           return std::string(kFormats[std::get<0>(info.param)].name) + "_" +
                                  short_name(std::get<1>(info.param));
                         });

}  // namespace
}  // namespace imx
