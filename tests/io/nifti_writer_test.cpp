#include <cstring>

#include <gtest/gtest.h>
#include <nifti/nifti1.h>

#include "expect_error.hpp"
#include "intermix/io.hpp"
#include "pattern_volume.hpp"
#include "temp_dir.hpp"

namespace imx {
namespace {

using test::expect_error;
using test::pattern_volume;
using test::TempDir;

TEST(NiftiWriter, KeepsAShearedAffineInTheSform) {
  // A gantry tilt: slices step along z and along y, so the affine is not a rotation.
  TempDir dir;
  VolumeData v = pattern_volume<int16_t>({4, 4, 4});
  v.index_to_world = glm::dmat4(1.0);
  v.index_to_world[0] = {0.5, 0.0, 0.0, 0.0};
  v.index_to_world[1] = {0.0, 0.5, 0.0, 0.0};
  v.index_to_world[2] = {0.0, 0.9, 2.5, 0.0};
  v.index_to_world[3] = {-120.25, 80.5, 33.0, 1.0};
  write_volume(v, dir / "tilt.nii.gz");
  // NIfTI stores the affine as float: entries come back within a float's rounding.
  test::expect_same_affine(read_volume(dir / "tilt.nii.gz").index_to_world, v.index_to_world, 1e-5);
}

TEST(NiftiWriter, WritesASingleFileNifti1HeaderInRas) {
  TempDir dir;
  VolumeData v = pattern_volume<uint8_t>({2, 3, 4});
  write_volume(v, dir / "h.nii");
  std::string bytes = test::read_bytes(dir / "h.nii");
  ASSERT_EQ(bytes.size(), 352u + 2 * 3 * 4);
  nifti_1_header h;
  std::memcpy(&h, bytes.data(), sizeof h);
  EXPECT_EQ(h.sizeof_hdr, 348);
  EXPECT_EQ(std::string(h.magic, 3), "n+1");
  EXPECT_EQ(h.vox_offset, 352.0f);
  EXPECT_EQ(h.datatype, DT_UINT8);
  EXPECT_EQ(h.sform_code, NIFTI_XFORM_SCANNER_ANAT);
  EXPECT_EQ(h.qform_code, NIFTI_XFORM_SCANNER_ANAT);
  // RAS: the LPS affine's x and y rows negated.
  for (int c = 0; c < 4; ++c) {
    EXPECT_NEAR(h.srow_x[c], -v.index_to_world[c][0], 1e-4) << c;
    EXPECT_NEAR(h.srow_y[c], -v.index_to_world[c][1], 1e-4) << c;
    EXPECT_NEAR(h.srow_z[c], v.index_to_world[c][2], 1e-4) << c;
  }
}

TEST(NiftiWriter, RefusesAnUnknownExtensionNamingTheFile) {
  TempDir dir;
  VolumeData v = pattern_volume<uint8_t>({2, 2, 2});
  EXPECT_FALSE(can_write_volume(dir / "v.png"));
  EXPECT_TRUE(can_write_volume(dir / "V.NII.GZ"));
  expect_error([&] { write_volume(v, dir / "v.png"); }, {"v.png", ".nii.gz"});
  EXPECT_TRUE(dir.entries().empty());
}

}  // namespace
}  // namespace imx
