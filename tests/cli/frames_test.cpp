// Multi-frame (4-D) sources on the command line: convert writes dcm2niix's 4-D NIfTI with its
// .bval/.bvec and a JSON sidecar, --frame picks one, render --frame-range renders a sequence.
// Uses ../shared/data/dicom4d (skipped without it).
#include <filesystem>
#include <fstream>
#include <vector>

#include <gtest/gtest.h>
#include <glm/geometric.hpp>
#include <glm/matrix.hpp>
#include <nlohmann/json.hpp>

#include "cli_runner.hpp"
#include "fsl_diffusion_files.hpp"
#include "intermix/dicom.hpp"
#include "intermix/io.hpp"
#include "scene_fixture.hpp"
#include "shared_data.hpp"
#include "temp_dir.hpp"

namespace imx {
namespace {

namespace fs = std::filesystem;
using test::read_rows;
using test::run_cli;
using test::TempDir;

fs::path dicom4d(const std::string& name) {
  return test::shared_data("dicom4d") / name;
}

glm::dvec3 bvec_world(const std::vector<std::vector<double>>& bvec, size_t f, const glm::dmat4& m) {
  return test::bvec_world(glm::dvec3(bvec[0][f], bvec[1][f], bvec[2][f]), m);
}

TEST(CliFrames, ConvertWritesTheWholeDiffusionSeriesAsDcm2niixDoes) {
  SKIP_WITHOUT_SHARED_DATA(dicom4d("xa30-dwi-10"));
  TempDir dir;
  const fs::path out = dir / "dwi.nii.gz";
  test::CliResult r = run_cli("convert " + dicom4d("xa30-dwi-10").string() + " -o " + out.string());
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const VolumeHeader mine = read_volume_header(out);
  const VolumeHeader ref = read_volume_header(dicom4d("ref/xa30-dwi-10.nii.gz"));
  EXPECT_EQ(mine.frames, 21);
  EXPECT_EQ(mine.frames, ref.frames);
  // The time step is RepetitionTime, as dcm2niix writes it (3.516 s).
  ASSERT_EQ(mine.frame_labels.size(), ref.frame_labels.size());
  ASSERT_TRUE(mine.frame_labels[1].time_s && ref.frame_labels[1].time_s);
  EXPECT_NEAR(*mine.frame_labels[1].time_s, *ref.frame_labels[1].time_s, 1e-4);
  const auto bval = read_rows(dir / "dwi.bval"), bvec = read_rows(dir / "dwi.bvec");
  const auto ref_bval = read_rows(dicom4d("ref/xa30-dwi-10.bval"));
  const auto ref_bvec = read_rows(dicom4d("ref/xa30-dwi-10.bvec"));
  ASSERT_EQ(bval.size(), 1u);
  ASSERT_EQ(bvec.size(), 3u);
  ASSERT_EQ(bval[0].size(), ref_bval[0].size());
  for (size_t f = 0; f < bval[0].size(); ++f) {
    EXPECT_NEAR(bval[0][f], ref_bval[0][f], 0.5) << f;
    const glm::dvec3 a = bvec_world(bvec, f, mine.index_to_world);
    const glm::dvec3 b = bvec_world(ref_bvec, f, ref.index_to_world);
    EXPECT_LT(glm::length(a - b), 1e-3) << "frame " << f;
  }
  std::ifstream sidecar(dir / "dwi.json");
  const nlohmann::json j = nlohmann::json::parse(sidecar);
  ASSERT_EQ(j["frames"].size(), 21u);
  EXPECT_EQ(j["frames"][1]["b_value"].get<double>(), 2500.0);
  // The 4-D file's frame 5 is the series' frame 5.
  DicomReadOptions o;
  o.frame = 5;
  const VolumeData five = read_dicom(dicom4d("xa30-dwi-10"), o).volume;
  const VolumeData written = read_volume(out, 5);
  ASSERT_EQ(written.dims, five.dims);
  for (int k = 0; k < five.dims.z; k += 7)
    for (int j2 = 0; j2 < five.dims.y; j2 += 5)
      for (int i = 0; i < five.dims.x; i += 3)
        ASSERT_EQ(written.value_at(i, j2, k), five.value_at(i, j2, k));
}

TEST(CliFrames, OneFrameWithFrameAndAClearErrorForOtherFormats) {
  SKIP_WITHOUT_SHARED_DATA(dicom4d("xa30-asl-25"));
  TempDir dir;
  const std::string asl = dicom4d("xa30-asl-25").string();
  test::CliResult r = run_cli("convert " + asl + " -o " + (dir / "asl.nrrd").string());
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.output.find("7 frames"), std::string::npos) << r.output;
  EXPECT_FALSE(fs::exists(dir / "asl.nrrd"));
  r = run_cli("convert " + asl + " --frame 6 -o " + (dir / "asl6.nrrd").string());
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_EQ(read_volume_header(dir / "asl6.nrrd").frames, 1);
  r = run_cli("convert " + asl + " --frame 7 -o " + (dir / "asl7.nrrd").string());
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.output.find("frame 7"), std::string::npos) << r.output;
  r = run_cli("info " + asl + " --series 25 --json");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const nlohmann::json info = nlohmann::json::parse(r.output);
  EXPECT_EQ(info["frames"].get<int>(), 7);
  EXPECT_EQ(info["frame_labels"].size(), 7u);
}

TEST(CliFrames, RenderFrameRangeWritesOneImagePerFrame) {
  SKIP_WITHOUT_SHARED_DATA(dicom4d("xa30-asl-25"));
  TempDir dir;
  dir.write("asl.json",
            test::scene_document({test::mip_volume("asl", dicom4d("xa30-asl-25"), 2000)}, 24,
                                 {0, 600, 40}, {0, 0, 40})
                .dump());
  const std::string out = (dir / "f_%02d.png").string();
  test::CliResult r =
      run_cli("render " + (dir / "asl.json").string() + " --frame-range 1:3 -o " + out);
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_FALSE(fs::exists(dir / "f_00.png"));
  for (const char* f : {"f_01.png", "f_02.png", "f_03.png"}) EXPECT_TRUE(fs::exists(dir / f)) << f;
  EXPECT_FALSE(fs::exists(dir / "f_04.png"));
  r = run_cli("render " + (dir / "asl.json").string() + " --frame-range 1:3 -o " +
              (dir / "plain.png").string());
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.output.find("%03d"), std::string::npos) << r.output;
}

}  // namespace
}  // namespace imx
