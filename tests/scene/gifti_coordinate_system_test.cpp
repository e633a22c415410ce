// GIfTI's coordinate systems (issue 46): vertices stored in FreeSurfer's tkr-RAS (DataSpace
// NIFTI_XFORM_UNKNOWN) with a CoordinateSystemTransformMatrix to NIFTI_XFORM_SCANNER_ANAT are
// placed by it, as nibabel reads the matrix (nibabel, /usr/bin/python3, writes the file and
// applies its matrix for reference), with a note; a matrix to a template space leaves them.
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include <fmt/format.h>
#include <gtest/gtest.h>

#include "cli_runner.hpp"
#include "expect_error.hpp"
#include "intermix/io.hpp"
#include "temp_dir.hpp"

namespace imx {
namespace {

namespace fs = std::filesystem;
using test::TempDir;

// Writes a tetrahedron GIfTI with nibabel whose vertices carry the coordinate system
// (dataspace, xformspace, a rotation about z by 30 degrees and a translation), and prints the
// vertices nibabel's matrix maps them to (RAS), one line each. Empty when nibabel is missing.
std::vector<glm::dvec3> write_with_nibabel(const TempDir& dir, const fs::path& file, int dataspace,
                                           int xformspace) {
  std::ofstream(dir / "make.py") << R"(import sys
import numpy as np
import nibabel as nib
from nibabel.affines import apply_affine
points = np.array([[10, 20, 30], [11, 20, 30], [10, 21, 30], [10, 20, 31]], np.float32)
faces = np.array([[0, 2, 1], [0, 1, 3], [0, 3, 2], [1, 2, 3]], np.int32)
a = np.radians(30)
m = np.array([[np.cos(a), -np.sin(a), 0, 5.5], [np.sin(a), np.cos(a), 0, -17.25],
              [0, 0, 1, 40], [0, 0, 0, 1]])
cs = nib.gifti.GiftiCoordSystem(int(sys.argv[2]), int(sys.argv[3]), m)
img = nib.gifti.GiftiImage(darrays=[
    nib.gifti.GiftiDataArray(points, intent="NIFTI_INTENT_POINTSET", coordsys=cs),
    nib.gifti.GiftiDataArray(faces, intent="NIFTI_INTENT_TRIANGLE")])
nib.save(img, sys.argv[1])
back = nib.load(sys.argv[1]).darrays[0]
for p in apply_affine(back.coordsys.xform, back.data):
    print("%.9g %.9g %.9g" % tuple(p))
)";
  const test::CliResult r =
      test::run_shell(fmt::format("/usr/bin/python3 {} {} {} {} 2>&1", (dir / "make.py").string(),
                                  file.string(), dataspace, xformspace));
  std::vector<glm::dvec3> out;
  if (r.exit_code != 0) return out;
  std::istringstream lines(r.output);
  for (glm::dvec3 p; lines >> p.x >> p.y >> p.z;) out.push_back(p);
  return out;
}

std::string joined(const std::vector<std::string>& notes) {
  std::string all;
  for (const std::string& n : notes) all += n + "\n";
  return all;
}

TEST(GiftiCoordinateSystem, TkrRasToScannerIsPlacedByTheMatrixAsNibabelReadsIt) {
  if (test::run_shell("/usr/bin/python3 -c 'import nibabel' 2>&1").exit_code != 0)
    GTEST_SKIP() << "/usr/bin/python3 has no nibabel";
  TempDir dir;
  const fs::path file = dir / "lh.pial.gii";
  const std::vector<glm::dvec3> expected =
      write_with_nibabel(dir, file, 0, 1);  // UNKNOWN -> SCANNER
  ASSERT_EQ(expected.size(), 4u);
  const MeshFile read = read_mesh_file(file);
  ASSERT_EQ(read.file_vertex.size(), read.mesh.positions.size());
  for (size_t i = 0; i < read.mesh.positions.size(); ++i) {  // split at the tetrahedron's edges
    const glm::dvec3 ras = expected.at(read.file_vertex[i]);
    const glm::dvec3 lps(-ras.x, -ras.y, ras.z);
    EXPECT_LT(glm::length(glm::dvec3(read.mesh.positions[i]) - lps), 1e-4) << i;
  }
  EXPECT_NE(joined(read.info.notes)
                .find("lh.pial.gii: GIfTI vertices in NIFTI_XFORM_UNKNOWN (DataSpace), moved to "
                      "NIFTI_XFORM_SCANNER_ANAT by the file's CoordinateSystemTransformMatrix "
                      "(translation 5.5 -17.25 40 mm)"),
            std::string::npos)
      << joined(read.info.notes);
}

TEST(GiftiCoordinateSystem, AMatrixToATemplateSpaceLeavesTheVerticesWithANote) {
  if (test::run_shell("/usr/bin/python3 -c 'import nibabel' 2>&1").exit_code != 0)
    GTEST_SKIP() << "/usr/bin/python3 has no nibabel";
  TempDir dir;
  const fs::path file = dir / "white.gii";
  ASSERT_EQ(write_with_nibabel(dir, file, 1, 3).size(), 4u);  // SCANNER -> TALAIRACH
  const MeshFile read = read_mesh_file(file);
  for (size_t i = 0; i < read.mesh.positions.size(); ++i)
    if (read.file_vertex[i] == 1) {
      EXPECT_EQ(read.mesh.positions[i], glm::vec3(-11, -20, 30));  // as stored, RAS to LPS
    }
  EXPECT_NE(joined(read.info.notes)
                .find("white.gii: the file's CoordinateSystemTransformMatrix maps "
                      "NIFTI_XFORM_SCANNER_ANAT to NIFTI_XFORM_TALAIRACH; the vertices stay in "
                      "their DataSpace, NIFTI_XFORM_SCANNER_ANAT"),
            std::string::npos)
      << joined(read.info.notes);
}

TEST(GiftiCoordinateSystem, AMatrixThatIsNotAnAffineMapIsOneClearError) {
  if (test::run_shell("/usr/bin/python3 -c 'import nibabel' 2>&1").exit_code != 0)
    GTEST_SKIP() << "/usr/bin/python3 has no nibabel";
  TempDir dir;
  const fs::path file = dir / "bad.gii";
  ASSERT_EQ(write_with_nibabel(dir, file, 0, 1).size(), 4u);
  std::string text = test::read_bytes(file);
  const size_t b = text.find("<MatrixData>"), e = text.find("</MatrixData>");
  ASSERT_TRUE(b != std::string::npos && e != std::string::npos);
  const std::string good = text;
  text.replace(b, e - b, "<MatrixData>1 0 0 0 0 1 0 0 0 0 1 0 0 0 1 1");
  test::write_bytes(file, text);
  test::expect_error([&] { read_mesh_file(file); },
                     {"bad.gii: the vertices' CoordinateSystemTransformMatrix's last row is 0 0 1 "
                      "1, not 0 0 0 1"});
  text = good;
  text.replace(b, e - b, "<MatrixData>1 0 0 0 0 1 nan 0");
  test::write_bytes(file, text);
  test::expect_error([&] { read_mesh_file(file); },
                     {"bad.gii: the vertices' CoordinateSystemTransformMatrix is not 16 finite "
                      "numbers"});
}

}  // namespace
}  // namespace imx
