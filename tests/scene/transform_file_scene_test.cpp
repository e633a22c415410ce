// Transforms from registration files in scenes: one known placement written in every format
// (by the conversions in registration_files.hpp, computed from each format's definition) puts a
// moving volume at the same place, checked at its 8 corners; "invert", relative paths, notes and
// the errors of a transform entry.
#include <cmath>
#include <cstdio>
#include <string>

#include <gtest/gtest.h>

#include "expect_error.hpp"
#include "intermix/io.hpp"
#include "intermix/scene.hpp"
#include "registration_files.hpp"
#include "scene_fixture.hpp"
#include "temp_dir.hpp"

namespace imx {
namespace {

const glm::dvec3 kCentre(3.0, -4.0, 5.0);

class TransformFiles : public ::testing::Test {
 protected:
  void SetUp() override {
    // Stored RAS (positive determinant: FSL flips its x), 20 x 24 x 16 voxels.
    moving_.dims = {20, 24, 16};
    moving_.voxels = std::vector<uint8_t>(20 * 24 * 16, 9);
    moving_.index_to_world = glm::dmat4(1.0);
    moving_.index_to_world[0][0] = -1.5;
    moving_.index_to_world[1][1] = -1.2;
    moving_.index_to_world[2][2] = 2.0;
    moving_.index_to_world[3] = glm::dvec4(30, 40, -20, 1);
    write_volume(moving_, dir_ / "moving.nii", false);
    reference_ = moving_;
    reference_.dims = {30, 28, 22};
    reference_.voxels = std::vector<uint8_t>(30 * 28 * 22, 1);
    reference_.index_to_world = glm::dmat4(1.0);
    reference_.index_to_world[2][2] = 1.25;
    reference_.index_to_world[1][1] = -1.0;
    reference_.index_to_world[3] = glm::dvec4(-15, 14, -13, 1);
    write_volume(reference_, dir_ / "reference.nii.gz", false);
    // As read back: NIfTI keeps the placement in float32.
    moving_.index_to_world = read_volume_header(dir_ / "moving.nii").index_to_world;
    reference_.index_to_world = read_volume_header(dir_ / "reference.nii.gz").index_to_world;
    write_all(test::known_placement());
  }

  // The placement `p` in every format, under reg/.
  void write_all(const glm::dmat4& p) {
    const glm::dmat4 itk = glm::inverse(p);  // ITK stores fixed to moving
    const std::vector<double> params = test::itk_affine_parameters(itk, kCentre);
    const std::vector<double> fixed = {kCentre.x, kCentre.y, kCentre.z};
    dir_.write("reg/slicer.tfm", test::itk_text("AffineTransform_double_3_3", params, fixed));
    dir_.write("reg/ants.txt",
               test::itk_text("MatrixOffsetTransformBase_double_3_3", params, fixed));
    dir_.write("reg/ants.mat", test::matlab_v4_vector("AffineTransform_float_3_3", params, true) +
                                   test::matlab_v4_vector("fixed", fixed, true));
    dir_.write("reg/itk.mat", test::matlab_v4_vector("AffineTransform_double_3_3", params) +
                                  test::matlab_v4_vector("fixed", fixed));
    // FSL: reference scaled voxels of the moving image's.
    const glm::dmat4 flirt = test::fsl_scaled(reference_.dims, {1.0, 1.0, 1.25}, false) *
                             glm::inverse(reference_.index_to_world) * p * moving_.index_to_world *
                             glm::inverse(test::fsl_scaled(moving_.dims, {1.5, 1.2, 2.0}, true));
    std::string fsl;
    for (int r = 0; r < 4; ++r)
      fsl += fmt::format("{:.17g}  {:.17g}  {:.17g}  {:.17g}  \n", flirt[0][r], flirt[1][r],
                         flirt[2][r], flirt[3][r]);
    dir_.write("reg/flirt.mat", fsl);
    // FreeSurfer: source (moving) to destination RAS, and the same in voxels.
    const glm::dmat4 ras = test::flip_xy() * p * test::flip_xy();
    const glm::dmat3 lia(glm::dvec3(-1, 0, 0), glm::dvec3(0, 0, -1), glm::dvec3(0, 1, 0));
    const glm::dvec3 sd(20, 24, 16), ss(1.5, 1.2, 2.0), sc(1, 2, 3);
    const glm::dvec3 dd(64, 64, 48), ds(1, 1, 1.5), dc(-4, 6, 8);
    const std::string src = test::lta_volume_block(sd, ss, lia, sc);
    const std::string dst = test::lta_volume_block(dd, ds, glm::dmat3(1.0), dc);
    dir_.write("reg/ras.lta", test::lta_text(1, ras, src, dst));
    const glm::dmat4 vox = glm::inverse(test::freesurfer_vox2ras(dd, ds, glm::dmat3(1.0), dc)) *
                           ras * test::freesurfer_vox2ras(sd, ss, lia, sc);
    dir_.write("reg/vox.lta", test::lta_text(0, vox, src, dst));
    // AFNI: base to source, LPS, one row.
    dir_.write("reg/afni.aff12.1D", test::joined(test::rows_of(itk)) + "\n");
  }

  Scene scene_with(const std::string& transform) const {
    return test::parse(test::with_objects(
                           R"({"name": "mov", "type": "volume", "source": {"file": "moving.nii"},
                               "transfer_function": {"points": [[0, 1, 1, 1, 0], [9, 1, 1, 1, 1]]},
                               "transform": )" +
                           transform + "}"),
                       {}, dir_.path());
  }

  // The largest distance, mm, between where the scene puts the moving volume's 8 corners and
  // where `placement` puts them.
  double worst_corner(const Scene& scene, const glm::dmat4& placement) const {
    const glm::dmat4 want = placement * moving_.index_to_world;
    const glm::dmat4& got = scene.volumes.at(0).index_to_world;
    const glm::dvec3 hi = glm::dvec3(moving_.dims) - 0.5;
    double worst = 0.0;
    for (int c = 0; c < 8; ++c) {
      const glm::dvec4 corner((c & 1) ? hi.x : -0.5, (c & 2) ? hi.y : -0.5, (c & 4) ? hi.z : -0.5,
                              1.0);
      worst = std::max(worst, glm::length(glm::dvec3(got * corner) - glm::dvec3(want * corner)));
    }
    return worst;
  }

  test::TempDir dir_;
  VolumeData moving_, reference_;
};

TEST_F(TransformFiles, EveryFormatPlacesTheVolumeAtTheSameCorners) {
  const glm::dmat4 p = test::known_placement();
  const std::string images = R"(, "moving": "moving.nii", "reference": "reference.nii.gz")";
  for (const char* file : {"slicer.tfm", "ants.txt", "ants.mat", "itk.mat", "flirt.mat", "ras.lta",
                           "vox.lta", "afni.aff12.1D"}) {
    const std::string name(file);
    const Scene scene =
        scene_with(R"({"file": "reg/)" + name + "\"" + (name == "flirt.mat" ? images : "") + "}");
    const double worst = worst_corner(scene, p);
    std::printf("%-14s worst corner %.2e mm\n", file, worst);
    EXPECT_LT(worst, 0.01) << file;
    // Double files are exact to rounding; ANTs' float file and FSL's float32 pixdim are not.
    EXPECT_LT(worst, name == "ants.mat" || name == "flirt.mat" ? 1e-4 : 1e-9) << file;
  }
}

TEST_F(TransformFiles, InvertPlacesTheFixedImageInTheMovingOnesSpace) {
  const Scene scene = scene_with(R"({"file": "reg/slicer.tfm", "invert": true})");
  EXPECT_LT(worst_corner(scene, glm::inverse(test::known_placement())), 1e-9);
  ASSERT_GE(scene.notes.size(), 1u);  // then "no camera: ..."
  EXPECT_CONTAINS(scene.notes[0], "objects[0].transform: slicer.tfm is an ITK text transform");
  EXPECT_CONTAINS(scene.notes[0], "fixed to moving");
  EXPECT_CONTAINS(scene.notes[0], "registration's fixed image");
  const Scene lta = scene_with(R"({"file": "reg/ras.lta"})");
  ASSERT_GE(lta.notes.size(), 1u);
  EXPECT_CONTAINS(lta.notes[0], "FreeSurfer LTA, stored moving to fixed");
}

TEST_F(TransformFiles, ErrorsNameTheTransformEntry) {
  auto error = [&](const std::string& transform) {
    return test::error_of([&] { scene_with(transform); });
  };
  std::string e = error(R"({"file": "reg/flirt.mat"})");
  EXPECT_CONTAINS(e, "objects[0].transform.file");
  EXPECT_CONTAINS(e, "name the images it was computed with");
  EXPECT_EQ(e.find('\n'), std::string::npos);
  e = error(R"({"file": "reg/flirt.mat", "moving": "moving.nii"})");
  EXPECT_CONTAINS(e, "\"reference\" is missing");
  e = error(R"({"file": "reg/flirt.mat", "moving": "moving.nii", "reference": "nothere.nii"})");
  EXPECT_CONTAINS(e, "objects[0].transform.reference");
  EXPECT_CONTAINS(e, "no such file");
  e = error(R"({"file": "reg/missing.tfm"})");
  EXPECT_CONTAINS(e, "no such file");
  e = error(R"({"translate": [1, 2, 3], "invert": true})");
  EXPECT_CONTAINS(e, "\"invert\" applies to a transform read from a \"file\"");
  e = error(R"({"file": "reg/slicer.tfm", "translate": [1, 2, 3]})");
  EXPECT_CONTAINS(e, "either \"file\" or an inline transform");
  e = error(R"({"file": "reg/slicer.tfm", "moving": "moving.nii"})");
  EXPECT_CONTAINS(e, "are for FSL FLIRT matrices");
  dir_.write("reg/flat.tfm", test::itk_text("AffineTransform_double_3_3",
                                            {1, 0, 0, 0, 1, 0, 2, 0, 0, 0, 0, 0}, {0, 0, 0}));
  e = error(R"({"file": "reg/flat.tfm"})");
  EXPECT_CONTAINS(e, "objects[0].transform.file");
  EXPECT_CONTAINS(e, "singular");
}

TEST_F(TransformFiles, ADisplacementFieldResamplesTheVolumeOnceOnItsOwnGrid) {
  // A constant field of (4, 0, 0) mm: each voxel takes the moving value 4 mm further along x.
  glm::dmat4 grid(3.0);
  grid[3] = glm::dvec4(-60, -60, -60, 1);
  dir_.write("reg/warp.nii", test::displacement_field_nifti({50, 50, 50}, grid, [](int, int, int) {
               return glm::dvec3(4, 0, 0);
             }));
  const Scene scene = scene_with(R"({"file": "reg/warp.nii"})");
  const VolumeData& v = *scene.volumes.at(0).data;
  EXPECT_EQ(v.type(), VoxelType::f32);
  EXPECT_EQ(v.dims, moving_.dims);
  EXPECT_EQ(scene.volumes[0].index_to_world, moving_.index_to_world);
  // The moving image is 9 everywhere: 9 where x + 4 mm stays inside it, no data beyond.
  EXPECT_FLOAT_EQ(static_cast<float>(v.value_at(10, 10, 8)), 9.0f);
  int nan = 0;
  for (int i = 0; i < v.dims.x; ++i) nan += std::isnan(v.value_at(i, 10, 8)) ? 1 : 0;
  EXPECT_EQ(nan, 3);  // x grows to the left as i falls (-1.5 mm a voxel): 4 mm is 2.7 voxels
  bool noted = false;
  for (const std::string& note : scene.notes)
    noted = noted || note.find("warp.nii is a displacement field") != std::string::npos;
  EXPECT_TRUE(noted);
  EXPECT_CONTAINS(
      test::error_of([&] { scene_with(R"({"file": "reg/warp.nii", "invert": true})"); }),
      "unknown key");
  EXPECT_CONTAINS(
      test::error_of([&] {
        test::parse(test::with_objects(test::mesh_json("m", R"("primitive": "sphere", "radius": 5)",
                                                       R"("transform": {"file": "reg/warp.nii"})")),
                    {}, dir_.path());
      }),
      "warps volumes only");
}

}  // namespace
}  // namespace imx
