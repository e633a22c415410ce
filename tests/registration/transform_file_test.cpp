// The transform readers against placements computed here from each format's definition: ITK
// (fixed to moving, with a centre), FSL FLIRT (scaled voxels, x flip), FreeSurfer LTA (RAS and
// voxel), AFNI (base to source, LPS); the ITK classes' parameter conventions on hand-worked
// points; and one clear line for each kind of bad file.
#include <cmath>
#include <functional>
#include <string>
#include <utility>
#include <vector>

#include <gtest/gtest.h>

#include "expect_error.hpp"
#include "intermix/io.hpp"
#include "linear_time.hpp"
#include "registration/transform_file.hpp"
#include "registration/transform_readers.hpp"
#include "registration_files.hpp"
#include "temp_dir.hpp"

namespace imx {
namespace {

using test::expect_error;

double max_difference(const glm::dmat4& a, const glm::dmat4& b) {
  double worst = 0.0;
  for (int c = 0; c < 4; ++c)
    for (int r = 0; r < 4; ++r) worst = std::max(worst, std::abs(a[c][r] - b[c][r]));
  return worst;
}

glm::dvec3 apply(const glm::dmat4& m, const glm::dvec3& p) {
  return glm::dvec3(m * glm::dvec4(p, 1.0));
}

void expect_near(const glm::dvec3& got, const glm::dvec3& want, double tolerance = 1e-9) {
  EXPECT_NEAR(got.x, want.x, tolerance);
  EXPECT_NEAR(got.y, want.y, tolerance);
  EXPECT_NEAR(got.z, want.z, tolerance);
}

// The map a fixed-to-moving ITK file stores: the inverse of the placement it is read as.
glm::dmat4 itk_map(const std::string& text) {
  return glm::inverse(parse_transform_file(text, "t.tfm").moving_to_fixed);
}

const glm::dvec3 kCentre(3.0, -4.0, 5.0);

TEST(ItkText, AffineWithACentreIsTheInverseOfThePlacement) {
  const glm::dmat4 p = test::known_placement();
  const std::string text = test::itk_text("AffineTransform_double_3_3",
                                          test::itk_affine_parameters(glm::inverse(p), kCentre),
                                          {kCentre.x, kCentre.y, kCentre.z});
  const FileTransform t = parse_transform_file(text, "reg.tfm");
  EXPECT_EQ(t.format, TransformFormat::itk_text);
  EXPECT_LT(max_difference(t.moving_to_fixed, p), 1e-9);
  // ANTs' text output: MatrixOffsetTransformBase, float parameters, .txt.
  const std::string ants = test::itk_text("MatrixOffsetTransformBase_float_3_3",
                                          test::itk_affine_parameters(glm::inverse(p), kCentre),
                                          {kCentre.x, kCentre.y, kCentre.z});
  EXPECT_LT(max_difference(parse_transform_file(ants, "0GenericAffine.txt").moving_to_fixed, p),
            1e-9);
}

// 3D Slicer saves a linear transform node as the ITK "from parent" map in LPS. A node moving
// its child by a 90 degree turn about S and then (10, 20, 30) mm RAS takes the child's point
// R = 1 (LPS (-1, 0, 0)) to RAS (0, 1, 0) + (10, 20, 30) = (10, 21, 30): LPS (-10, -21, 30).
// Its file (worked out by hand: from-parent RAS = Rz(-90) q + (-20, 10, -30); in LPS the turn
// is the same and the shift (20, -10, -30)):
TEST(ItkText, ASlicerFilePlacesTheMovingVolumeWhereSlicerDoes) {
  const std::string slicer =
      "#Insight Transform File V1.0\n"
      "#Transform 0\n"
      "Transform: AffineTransform_double_3_3\n"
      "Parameters: 0 1 0 -1 0 0 0 0 1 20 -10 -30\n"
      "FixedParameters: 0 0 0\n";
  const glm::dmat4 placement = parse_transform_file(slicer, "Transform.tfm").moving_to_fixed;
  expect_near(apply(placement, {-1, 0, 0}), {-10, -21, 30});
  // The origin goes where the node's shift alone takes it: RAS (10, 20, 30), LPS (-10, -20, 30).
  expect_near(apply(placement, {0, 0, 0}), {-10, -20, 30});
}

TEST(ItkText, EulerAnglesTurnYThenXThenZUnlessComputeZYX) {
  // Quarter turns about x and y. Y first: (1, 0, 0) -> (0, 0, -1), then X: -> (0, 1, 0).
  const double q = std::acos(0.0);
  const std::string zxy =
      test::itk_text("Euler3DTransform_double_3_3", {q, q, 0, 0, 0, 0}, {0, 0, 0, 0});
  expect_near(apply(itk_map(zxy), {1, 0, 0}), {0, 1, 0});
  // ComputeZYX (the fourth fixed parameter): X first: (1, 0, 0) stays, then Y: -> (0, 0, -1).
  const std::string zyx =
      test::itk_text("Euler3DTransform_double_3_3", {q, q, 0, 0, 0, 0}, {0, 0, 0, 1});
  expect_near(apply(itk_map(zyx), {1, 0, 0}), {0, 0, -1});
  // Older files have three fixed parameters: the default order.
  const std::string old =
      test::itk_text("Euler3DTransform_double_3_3", {q, q, 0, 0, 0, 0}, {0, 0, 0});
  expect_near(apply(itk_map(old), {1, 0, 0}), {0, 1, 0});
  // About a centre, then translated: T(x) = R (x - c) + c + t. A quarter turn about z at
  // c = (10, 0, 0) takes (11, 0, 0) to (10, 1, 0); t = (0, 0, 5) lifts it.
  const std::string centred =
      test::itk_text("Euler3DTransform_double_3_3", {0, 0, q, 0, 0, 5}, {10, 0, 0});
  expect_near(apply(itk_map(centred), {11, 0, 0}), {10, 1, 5});
}

TEST(ItkText, VersorAndSimilarity) {
  // The versor of a quarter turn about z: vector part (0, 0, sin 45).
  const double s = std::sqrt(0.5);
  const std::string versor =
      test::itk_text("VersorRigid3DTransform_double_3_3", {0, 0, s, 1, 2, 3}, {0, 0, 0});
  expect_near(apply(itk_map(versor), {1, 0, 0}), {1, 3, 3});
  // Similarity: 2 R (x - c) + c + t with c = (1, 1, 1): (2, 1, 1) -> c + 2 (0, 1, 0) + t.
  const std::string similarity =
      test::itk_text("Similarity3DTransform_double_3_3", {0, 0, s, 0, 0, -1, 2}, {1, 1, 1});
  expect_near(apply(itk_map(similarity), {2, 1, 1}), {1, 3, 0});
  // A translation alone (no fixed parameters).
  const std::string shift =
      "#Insight Transform File V1.0\n#Transform 0\n"
      "Transform: TranslationTransform_double_3_3\nParameters: 4 5 6\n"
      "FixedParameters:\n";
  expect_near(apply(itk_map(shift), {1, 1, 1}), {5, 6, 7});
}

TEST(ItkText, ACompositeAppliesItsLastTransformFirst) {
  // [scale 2, translate (1, 0, 0)]: x -> 2 (x + (1, 0, 0)), so the origin goes to (2, 0, 0).
  const std::string composite =
      "#Insight Transform File V1.0\n#Transform 0\nTransform: CompositeTransform_double_3\n"
      "#Transform 1\nTransform: AffineTransform_double_3_3\n"
      "Parameters: 2 0 0 0 2 0 0 0 2 0 0 0\nFixedParameters: 0 0 0\n"
      "#Transform 2\nTransform: TranslationTransform_double_3_3\nParameters: 1 0 0\n"
      "FixedParameters:\n";
  expect_near(apply(itk_map(composite), {0, 0, 0}), {2, 0, 0});
}

TEST(ItkMatlab, VectorsAsVnlWritesThemInEitherByteOrderAndPrecision) {
  const glm::dmat4 p = test::known_placement();
  const std::vector<double> parameters = test::itk_affine_parameters(glm::inverse(p), kCentre);
  const std::vector<double> fixed = {kCentre.x, kCentre.y, kCentre.z};
  const std::string little = test::matlab_v4_vector("AffineTransform_double_3_3", parameters) +
                             test::matlab_v4_vector("fixed", fixed);
  const FileTransform t = parse_transform_file(little, "0GenericAffine.mat");
  EXPECT_EQ(t.format, TransformFormat::itk_matlab);
  EXPECT_LT(max_difference(t.moving_to_fixed, p), 1e-9);
  const std::string big_float =
      test::matlab_v4_vector("AffineTransform_float_3_3", parameters, true, true) +
      test::matlab_v4_vector("fixed", fixed, true, true);
  EXPECT_LT(max_difference(parse_transform_file(big_float, "a.mat").moving_to_fixed, p), 1e-4);
}

// The same transform written by scipy.io.savemat(format="4") from numpy (the placement and
// conversion computed there on their own): {"AffineTransform_double_3_3": 12 x 1, "fixed": 3 x 1}.
TEST(ItkMatlab, AFileScipyWrote) {
  const std::string hex =
      "000000000c00000001000000000000001b000000416666696e655472616e73666f726d5f646f75626c655f"
      "335f330065f82449feb0e63fa227c1e9ef02c83f3312b72c892fe1bfe83198425b46dbbfe05eb4aa5910f0"
      "3f5a342ebd2423cbbf0832c6475b57d83ff2ca37b0747bd23ff0b750332b4ce33feacf9d12ab321140e840"
      "82efa09c3040d1a5cb5f34c036c00000000003000000010000000000000006000000666978656400000000"
      "000000084000000000000010c00000000000001440";
  std::string bytes;
  for (size_t i = 0; i + 1 < hex.size(); i += 2)
    bytes += static_cast<char>(std::stoi(hex.substr(i, 2), nullptr, 16));
  ASSERT_EQ(bytes.size(), 193u);
  EXPECT_LT(max_difference(parse_transform_file(bytes, "scipy.mat").moving_to_fixed,
                           test::known_placement()),
            1e-9);
}

class FslFlirt : public ::testing::Test {
 protected:
  void SetUp() override {
    // Moving: stored as RAS (neurological: positive determinant), so FSL flips its x. Reference:
    // LAS (radiological), no flip.
    moving_ = volume({20, 24, 16}, {-1.5, -1.2, 2.0}, {30, 40, -20});
    reference_ = volume({30, 28, 22}, {1.0, -1.0, 1.25}, {-15, 14, -13});
    write_volume(moving_, dir_ / "moving.nii", false);
    write_volume(reference_, dir_ / "reference.nii.gz", false);
  }
  static VolumeData volume(glm::ivec3 dims, glm::dvec3 diagonal, glm::dvec3 origin) {
    VolumeData v;
    v.dims = dims;
    v.voxels = std::vector<uint8_t>(static_cast<size_t>(dims.x) * dims.y * dims.z, 7);
    v.index_to_world = glm::dmat4(1.0);
    for (int a = 0; a < 3; ++a) v.index_to_world[a][a] = diagonal[a];
    v.index_to_world[3] = glm::dvec4(origin, 1.0);
    return v;
  }
  // FLIRT's matrix of the placement: reference scaled voxels of moving scaled voxels.
  glm::dmat4 flirt(const glm::dmat4& placement) const {
    const glm::dmat4 in = test::fsl_scaled(moving_.dims, {1.5, 1.2, 2.0}, true);
    const glm::dmat4 ref = test::fsl_scaled(reference_.dims, {1.0, 1.0, 1.25}, false);
    return ref * glm::inverse(reference_.index_to_world) * placement * moving_.index_to_world *
           glm::inverse(in);
  }
  test::TempDir dir_;
  VolumeData moving_, reference_;
};

TEST_F(FslFlirt, ScaledVoxelsWithTheNeurologicalFlip) {
  const glm::dmat4 p = test::known_placement();
  const glm::dmat4 m = flirt(p);
  std::string text;
  for (int r = 0; r < 4; ++r)
    text +=
        fmt::format("{:.17g}  {:.17g}  {:.17g}  {:.17g}  \n", m[0][r], m[1][r], m[2][r], m[3][r]);
  const auto file = dir_.write("in2ref.mat", text);
  const FileTransform t =
      read_transform_file(file, {dir_ / "moving.nii", dir_ / "reference.nii.gz"});
  EXPECT_EQ(t.format, TransformFormat::fsl_flirt);
  EXPECT_LT(max_difference(t.moving_to_fixed, p), 1e-9);
  // Without its images: one line naming them.
  expect_error([&] { read_transform_file(file); }, {"in2ref.mat", "\"moving\"", "\"reference\""});
  expect_error(
      [&] {
        read_transform_file(file, {dir_ / "moving.nii", {}});
      },
      {"\"reference\" is missing"});
  // FSL's images are NIfTI.
  write_volume(moving_, dir_ / "moving.nrrd");
  expect_error(
      [&] {
        read_transform_file(file, {dir_ / "moving.nrrd", dir_ / "reference.nii.gz"});
      },
      {"moving.nrrd", "not NIfTI"});
}

TEST(FreeSurferLta, RasToRasAndVoxToVox) {
  const glm::dmat4 p = test::known_placement();
  const glm::dmat4 ras = test::flip_xy() * p * test::flip_xy();  // src (moving) to dst RAS
  const glm::dmat3 lia(glm::dvec3(-1, 0, 0), glm::dvec3(0, 0, -1), glm::dvec3(0, 1, 0));
  const glm::dvec3 src_dims(20, 24, 16), src_size(1.5, 1.2, 2.0), src_c(3, -4, 5);
  const glm::dvec3 dst_dims(256, 256, 256), dst_size(1, 1, 1), dst_c(-1.5, 12, 20);
  const std::string src = test::lta_volume_block(src_dims, src_size, lia, src_c);
  const std::string dst = test::lta_volume_block(dst_dims, dst_size, glm::dmat3(1.0), dst_c);
  const FileTransform r2r = parse_transform_file(test::lta_text(1, ras, src, dst), "reg.lta");
  EXPECT_EQ(r2r.format, TransformFormat::freesurfer_lta);
  EXPECT_LT(max_difference(r2r.moving_to_fixed, p), 1e-9);
  const glm::dmat4 vox =
      glm::inverse(test::freesurfer_vox2ras(dst_dims, dst_size, glm::dmat3(1.0), dst_c)) * ras *
      test::freesurfer_vox2ras(src_dims, src_size, lia, src_c);
  EXPECT_LT(max_difference(
                parse_transform_file(test::lta_text(0, vox, src, dst), "v.lta").moving_to_fixed, p),
            1e-9);
  expect_error([&] { parse_transform_file(test::lta_text(0, vox, "valid = 0\n", dst), "v.lta"); },
               {"v.lta", "src volume info"});
  expect_error([&] { parse_transform_file(test::lta_text(2, vox, src, dst), "v.lta"); },
               {"transform type 2"});
  // A degenerate grid is named, not found later as a "non-finite entry" of a singular matrix.
  const std::string flat = test::lta_volume_block(src_dims, glm::dvec3(0), lia, src_c);
  expect_error([&] { parse_transform_file(test::lta_text(0, vox, flat, dst), "v.lta"); },
               {"v.lta", "src volume info: voxelsize 0 0 0", "positive"});
  const std::string no_axis = test::lta_volume_block(dst_dims, dst_size, glm::dmat3(0.0), dst_c);
  expect_error([&] { parse_transform_file(test::lta_text(0, vox, src, no_axis), "v.lta"); },
               {"v.lta", "dst volume info: xras 0 0 0 is not a direction"});
}

TEST(AfniAff12, BaseToSourceInLps) {
  const glm::dmat4 p = test::known_placement();
  const std::string row = test::joined(test::rows_of(glm::inverse(p)));
  const FileTransform t = parse_transform_file(
      "# 3dAllineate matrices (DICOM-to-DICOM, row-by-row):\n" + row + "\n", "mov_al.aff12.1D");
  EXPECT_EQ(t.format, TransformFormat::afni_aff12);
  EXPECT_LT(max_difference(t.moving_to_fixed, p), 1e-9);
  std::vector<double> v = test::rows_of(glm::inverse(p));
  std::string three;
  for (int r = 0; r < 3; ++r)
    three += test::joined({v[4 * r], v[4 * r + 1], v[4 * r + 2], v[4 * r + 3]}) + "\n";
  EXPECT_LT(max_difference(parse_transform_file(three, "m.1D").moving_to_fixed, p), 1e-9);
  expect_error([&] { parse_transform_file(row + "\n" + row + "\n", "m.aff12.1D"); },
               {"2 rows of 12", "one matrix"});
}

TEST(BadTransformFiles, OneClearLineEach) {
  const std::string affine =
      "#Insight Transform File V1.0\nTransform: AffineTransform_double_3_3\n";
  // Singular.
  expect_error(
      [&] {
        parse_transform_file(
            affine + "Parameters: 1 0 0 0 1 0 0 0 0 0 0 0\nFixedParameters: 0 0 0\n", "flat.tfm");
      },
      {"flat.tfm", "singular"});
  expect_error([&] { parse_transform_file("1 0 0 0\n0 1 0 0\n0 0 0 0\n", "flat.aff12.1D"); },
               {"flat.aff12.1D", "singular"});
  expect_error([&] { parse_transform_file("1 0 0 0 0 1 0 0 0 0 0 0\n", "flat.aff12.1D"); },
               {"singular"});
  // Truncated.
  expect_error(
      [&] { parse_transform_file(affine + "Parameters: 1 0 0 0 1 0 0 0 1 0 0 0\n", "cut.tfm"); },
      {"cut.tfm", "no FixedParameters line", "truncated"});
  expect_error(
      [&] {
        parse_transform_file(affine + "Parameters: 1 0 0 0 1 0\nFixedParameters: 0 0 0\n",
                             "cut.tfm");
      },
      {"6 parameters; it takes 12"});
  const std::string mat =
      test::matlab_v4_vector("AffineTransform_double_3_3", {1, 0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0}) +
      test::matlab_v4_vector("fixed", {0, 0, 0});
  expect_error([&] { parse_transform_file(mat.substr(0, 60), "cut.mat"); },
               {"cut.mat", "truncated"});
  expect_error([&] { parse_transform_file(mat.substr(0, 145), "cut.mat"); },
               {"truncated", "fixed"});
  expect_error([&] { parse_transform_file("1 0 0 0\n0 1 0 0\n0 0 1", "cut.mat"); },
               {"cut.mat", "11 numbers", "truncated"});
  expect_error(
      [&] { parse_transform_file("type = 1\nnxforms = 1\n1 4 4\n1 0 0 0\n0 1 0 0\n", "cut.lta"); },
      {"cut.lta", "8 matrix entries", "truncated"});
  expect_error([&] { parse_transform_file("1 0 0 0 0 1 0 0 0 0 1", "cut.aff12.1D"); },
               {"11 numbers", "truncated"});
  // Unknown transform type.
  expect_error(
      [&] {
        parse_transform_file(
            "#Insight Transform File V1.0\nTransform: BSplineTransform_double_3_3\n"
            "Parameters: 1 2 3\nFixedParameters: 0\n",
            "warp.tfm");
      },
      {"warp.tfm", "unknown transform type 'BSplineTransform_double_3_3'"});
  expect_error(
      [&] {
        parse_transform_file(
            test::matlab_v4_vector("ThinPlateSplineKernelTransform_double_3_3", {1}) +
                test::matlab_v4_vector("fixed", {0}),
            "tps.mat");
      },
      {"unknown transform type"});
  expect_error([&] { parse_transform_file("MATLAB 5.0 MAT-file, Platform: GLNXA64", "v5.mat"); },
               {"v5.mat", "MATLAB 5/7", "not read"});
  expect_error([&] { parse_transform_file("1 0 0 0\n", "reg.xfm"); },
               {"reg.xfm", "'.xfm' is not a transform format", ".lta"});
  // NaN entries.
  expect_error(
      [&] {
        parse_transform_file(
            affine + "Parameters: 1 0 0 0 nan 0 0 0 1 0 0 0\nFixedParameters: 0 0 0\n", "nan.tfm");
      },
      {"nan.tfm", "line 3 (Parameters)", "not a finite number"});
  expect_error(
      [&] {
        parse_transform_file(test::matlab_v4_vector("AffineTransform_double_3_3",
                                                    {1, 0, 0, 0, 1, 0, 0, 0, 1, NAN, 0, 0}) +
                                 test::matlab_v4_vector("fixed", {0, 0, 0}),
                             "nan.mat");
      },
      {"nan.mat", "not a finite number"});
  expect_error([&] { parse_transform_file("NaN 0 0 0 0 1 0 0 0 0 1 0\n", "nan.aff12.1D"); },
               {"nan.aff12.1D", "not a finite number"});
  // Images where none are needed.
  expect_error(
      [&] {
        parse_transform_file(
            affine + "Parameters: 1 0 0 0 1 0 0 0 1 0 0 0\nFixedParameters: 0 0 0\n", "a.tfm",
            {"m.nii", "r.nii"});
      },
      {"a.tfm", "FSL FLIRT matrices"});
  // Not a regular file, too large.
  test::TempDir dir;
  expect_error([&] { read_transform_file(dir.path()); }, {"directory"});
  const auto big = dir.write("big.tfm", std::string(kMaxTransformFileBytes + 1, '#'));
  expect_error([&] { read_transform_file(big); }, {"big.tfm", "at most"});
}

// Every transform format's text at the 1 MiB a transform file may have against a sixteenth of
// it (issue 48, item 3): an ITK composite of many affines, an LTA whose volume info repeats its
// fields, an AFNI and an FSL matrix after many comment or blank lines.
TEST(TransformFile, EveryFormatIsReadInLinearTime) {
  constexpr size_t kLimit = kMaxTransformFileBytes;
  const std::string lta_head =
      "type      = 1 # LINEAR_RAS_TO_RAS\nnxforms   = 1\nmean      = 0 0 0\nsigma     = 1\n"
      "1 4 4\n1 0 0 2\n0 1 0 3\n0 0 1 4\n0 0 0 1\nsrc volume info\nvalid = 1\n"
      "dst volume info\nvalid = 1\n";
  const std::string affine = "1 0 0 0\n0 1 0 0\n0 0 1 0\n0 0 0 1\n";
  struct Case {
    const char* name;
    std::string head, unit, tail;
    std::function<void(const std::string&)> parse;
  };
  const std::vector<Case> cases = {
      {"ITK composite",
       "#Insight Transform File V1.0\n#Transform 0\nTransform: CompositeTransform_double_3\n",
       "#Transform 1\nTransform: AffineTransform_double_3_3\nParameters: 1 0 0 0 1 0 0 0 1 0.5 0 "
       "0\nFixedParameters: 0 0 0\n",
       "", [](const std::string& t) { parse_transform_file(t, "t.tfm"); }},
      {"FreeSurfer LTA", lta_head, "volume = 256 256 256\nvoxelsize = 1 1 1\n", "",
       [](const std::string& t) { detail::read_lta(t, "t.lta"); }},
      {"AFNI", "", "# 3dAllineate matrix, a comment line\n", "1 0 0 0 0 1 0 0 0 0 1 0\n",
       [](const std::string& t) { detail::read_afni_aff12(t, "t.aff12.1D"); }},
      {"FSL", "", "   \n", affine,
       [](const std::string& t) { detail::read_fsl_matrix(t, "t.mat"); }},
  };
  for (const Case& c : cases) {
    SCOPED_TRACE(c.name);
    auto text = [&](size_t bytes) {
      return test::repeated_to(c.head, c.unit, bytes - c.tail.size()) + c.tail;
    };
    const std::string full = text(kLimit), part = text(kLimit / 16);
    ASSERT_NO_THROW(c.parse(full));
    EXPECT_LE(test::growth_over_linear(c.parse, full, part), test::kMaxGrowthOverLinear)
        << "time(n) / (16 time(n/16))";
  }
}

}  // namespace
}  // namespace imx
