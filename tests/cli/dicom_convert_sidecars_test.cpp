// `intermix convert` of DICOM series beside dcm2niix: .bval/.bvec written for the same series as
// dcm2niix writes them (diffusion, not fMRI or ASL), and GE's diffusion directions equal to
// dcm2niix's in world space. Skipped without ../shared/data, pydicom or dcm2niix.
#include <filesystem>
#include <string>
#include <vector>

#include <fmt/format.h>
#include <gtest/gtest.h>
#include <glm/geometric.hpp>

#include "cli_runner.hpp"
#include "fsl_diffusion_files.hpp"
#include "intermix/io.hpp"
#include "pydicom_series.hpp"
#include "shared_data.hpp"
#include "temp_dir.hpp"

namespace imx {
namespace {

namespace fs = std::filesystem;
using test::read_rows;
using test::run_cli;
using test::TempDir;

// convert's .bval/.bvec exist exactly where dcm2niix's do, for the series `in`.
void expect_sidecars_as_dcm2niix(const fs::path& in, const TempDir& dir, const std::string& what) {
  ASSERT_TRUE(test::run_dcm2niix(in, dir / "ref", "x"));
  fs::create_directories(dir / "mine");
  const test::CliResult r =
      run_cli(fmt::format("convert '{}' -o '{}'", in.string(), (dir / "mine" / "x.nii").string()));
  ASSERT_EQ(r.exit_code, 0) << r.output;
  for (const char* ext : {".bval", ".bvec"})
    EXPECT_EQ(fs::exists(dir / "mine" / (std::string("x") + ext)),
              fs::exists(dir / "ref" / (std::string("x") + ext)))
        << what << ext;
}

// Series that are not diffusion (ASL, fMRI): dcm2niix writes no .bval/.bvec; neither does
// convert. The diffusion series: both write them.
TEST(CliConvertSidecars, BvalBvecOnlyWhereDcm2niixWritesThem) {
  SKIP_WITHOUT_SHARED_DATA("dicom4d");
  if (!test::have_pydicom_and_dcm2niix()) GTEST_SKIP() << "dcm2niix is not available";
  for (const char* name : {"xa30-asl-25", "mosaic-ep2d_Asc_2", "xa30-dwi-10"}) {
    TempDir dir;
    expect_sidecars_as_dcm2niix(test::shared_data("dicom4d") / name, dir, name);
  }
}

// Three volumes whose every image says b = 0 (Siemens (0019,xx0C), as some fMRI and field map
// series carry it): not diffusion for dcm2niix, which writes no .bval/.bvec; neither does convert.
TEST(CliConvertSidecars, NoBvalBvecWhereEveryBValueIsZero) {
  SKIP_WITHOUT_PYDICOM_AND_DCM2NIIX();
  TempDir dir;
  ASSERT_TRUE(test::run_pydicom(dir, R"PY(
orient = rotated_axial(10)
pos = positions(orient, 4, 3.0)
os.makedirs('in', exist_ok=True)
inst = 0
for v in range(3):
    for s in range(4):
        inst += 1
        def extra(ds, v=v):
            ds.AcquisitionTime = '1200%02d' % (v * 4)
            ds.add_new(0x00190010, 'LO', 'SIEMENS MR HEADER')
            ds.add_new(0x0019100C, 'IS', 0)
        write('in/IM%04d.dcm' % inst, 48, 40, pos[s], orient, pixels(48, 40, 1.0 / (1 + v)),
              '1.2.3.15', inst, extra, manufacturer='SIEMENS')
)PY"));
  expect_sidecars_as_dcm2niix(dir / "in", dir, "b = 0 only");
  EXPECT_TRUE(fs::exists(dir / "mine" / "x.nii"));
}

// A GE DWI turned 43 degrees in plane (directions in GE's image frame, (0019,10BB-BD)): the
// .bvec convert writes gives, through its NIfTI's affine, the world directions dcm2niix's .bvec
// gives through its own, to 1e-3; the .bval equals dcm2niix's.
TEST(CliConvertSidecars, GeObliqueBvecEqualsDcm2niixsInWorldSpace) {
  SKIP_WITHOUT_PYDICOM_AND_DCM2NIIX();
  TempDir dir;
  ASSERT_TRUE(test::run_pydicom(dir, R"PY(
orient = rotated_axial(43)
dirs = [(0, 0, 0, 0), (1000, 0.8, 0.36, 0.48), (1000, -0.3, 0.9, 0.3162), (1000, 0.6, 0.0, -0.8),
        (1000, 0.0, -0.6, 0.8)]
pos = positions(orient, 4, 3.0)
os.makedirs('in', exist_ok=True)
inst = 0
for v, (b, x, y, z) in enumerate(dirs):
    for s in range(4):
        inst += 1
        def extra(ds, b=b, x=x, y=y, z=z):
            ds.add_new(0x00190010, 'LO', 'GEMS_ACQU_01')
            ds.add_new(0x001910BB, 'DS', str(x))
            ds.add_new(0x001910BC, 'DS', str(y))
            ds.add_new(0x001910BD, 'DS', str(z))
            ds.add_new(0x00430010, 'LO', 'GEMS_PARM_01')
            ds.add_new(0x00431039, 'IS', [b, 8, 0, 0])
        write('in/IM%04d.dcm' % inst, 48, 40, pos[s], orient, pixels(48, 40, 1.0 / (1 + v) + 0.05 * s),
              '1.2.826.0.1.3680043.8.498.77', inst, extra)
)PY"));
  ASSERT_TRUE(test::run_dcm2niix(dir / "in", dir / "ref", "dwi"));
  fs::create_directories(dir / "mine");
  const test::CliResult r = run_cli(fmt::format("convert '{}' -o '{}'", (dir / "in").string(),
                                                (dir / "mine" / "dwi.nii").string()));
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const auto bval = read_rows(dir / "mine" / "dwi.bval"),
             ref_bval = read_rows(dir / "ref" / "dwi.bval");
  const auto bvec = read_rows(dir / "mine" / "dwi.bvec"),
             ref_bvec = read_rows(dir / "ref" / "dwi.bvec");
  ASSERT_EQ(bval.size(), 1u);
  ASSERT_EQ(ref_bval.size(), 1u);
  ASSERT_EQ(bvec.size(), 3u);
  ASSERT_EQ(ref_bvec.size(), 3u);
  ASSERT_EQ(bval[0].size(), ref_bval[0].size());
  const glm::dmat4 mine = read_volume_header(dir / "mine" / "dwi.nii").index_to_world;
  const glm::dmat4 ref = read_volume_header(dir / "ref" / "dwi.nii").index_to_world;
  for (size_t f = 0; f < bval[0].size(); ++f) {
    EXPECT_NEAR(bval[0][f], ref_bval[0][f], 0.5) << f;
    const glm::dvec3 ours = test::bvec_world(glm::dvec3(bvec[0][f], bvec[1][f], bvec[2][f]), mine);
    const glm::dvec3 theirs =
        test::bvec_world(glm::dvec3(ref_bvec[0][f], ref_bvec[1][f], ref_bvec[2][f]), ref);
    EXPECT_LT(glm::length(ours - theirs), 1e-3) << "volume " << f;
  }
}

}  // namespace
}  // namespace imx
