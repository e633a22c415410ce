// A legacy VTK file's field data (issue 46): 3D Slicer's SPACE string array (FIELD FieldData,
// as VTK's own vtkPolyDataWriter writes it, ASCII and BINARY, through python3-vtk9) names the
// mesh's space, as a VTP's field data and a title line's SPACE= already did. Other string arrays
// are read past; a SPACE that contradicts the title line is one clear error.
#include <filesystem>
#include <fstream>
#include <string>

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

// Writes the tetrahedron with VTK (ascii or binary) and field data SPACE = `space`, and a string
// array "Note" holding `note` (spaces and a percent sign: VTK escapes them in ASCII).
bool write_with_vtk(const TempDir& dir, const fs::path& file, bool binary, const std::string& space,
                    const std::string& title = "vtk output") {
  std::ofstream(dir / "make.py") << R"(import sys
import vtk
pts = vtk.vtkPoints()
for p in [(10, 20, 30), (11, 20, 30), (10, 21, 30), (10, 20, 31)]:
    pts.InsertNextPoint(p)
polys = vtk.vtkCellArray()
for f in [(0, 2, 1), (0, 1, 3), (0, 3, 2), (1, 2, 3)]:
    polys.InsertNextCell(3)
    for i in f:
        polys.InsertCellPoint(i)
pd = vtk.vtkPolyData()
pd.SetPoints(pts)
pd.SetPolys(polys)
note = vtk.vtkStringArray()
note.SetName("Note")
note.InsertNextValue("made by 100% VTK")
note.InsertNextValue("x" * 70)
pd.GetFieldData().AddArray(note)
s = vtk.vtkStringArray()
s.SetName("SPACE")
s.InsertNextValue(sys.argv[3])
pd.GetFieldData().AddArray(s)
w = vtk.vtkPolyDataWriter()
w.SetInputData(pd)
w.SetFileName(sys.argv[1])
w.SetHeader(sys.argv[4])
w.SetFileType(2 if sys.argv[2] == "binary" else 1)
w.Write()
)";
  return test::run_shell(fmt::format("/usr/bin/python3 {} {} {} {} '{}' 2>&1",
                                     (dir / "make.py").string(), file.string(),
                                     binary ? "binary" : "ascii", space, title))
             .exit_code == 0;
}

bool has_vtk() {
  return test::run_shell("/usr/bin/python3 -c 'import vtk' 2>&1").exit_code == 0;
}

TEST(VtkFieldSpace, SlicersSpaceFieldNamesTheSpaceInAsciiAndBinary) {
  if (!has_vtk()) GTEST_SKIP() << "/usr/bin/python3 has no vtk (python3-vtk9)";
  TempDir dir;
  for (const bool binary : {false, true})
    for (const char* space : {"RAS", "LPS"}) {
      SCOPED_TRACE(fmt::format("{} {}", binary ? "binary" : "ascii", space));
      const fs::path file = dir / fmt::format("t-{}-{}.vtk", binary, space);
      ASSERT_TRUE(write_with_vtk(dir, file, binary, space));
      const MeshFile read = read_mesh_file(file);
      EXPECT_EQ(read.info.space_source, MeshSpaceSource::header);
      EXPECT_EQ(read.info.space, std::string(space) == "RAS" ? MeshSpace::ras : MeshSpace::lps);
      const float s = std::string(space) == "RAS" ? -1.0f : 1.0f;
      for (size_t i = 0; i < read.mesh.positions.size(); ++i)
        if (read.file_vertex[i] == 1) {
          EXPECT_EQ(read.mesh.positions[i], glm::vec3(11 * s, 20 * s, 30));
        }
    }
}

TEST(VtkFieldSpace, ASpaceFieldThatContradictsTheTitleOrIsNoSpaceIsOneClearError) {
  if (!has_vtk()) GTEST_SKIP() << "/usr/bin/python3 has no vtk (python3-vtk9)";
  TempDir dir;
  const fs::path both = dir / "both.vtk";
  ASSERT_TRUE(write_with_vtk(dir, both, false, "RAS", "3D Slicer output. SPACE=RAS"));
  EXPECT_EQ(read_mesh_file(both).info.space, MeshSpace::ras);  // the two agree
  const fs::path contradicts = dir / "contradicts.vtk";
  ASSERT_TRUE(write_with_vtk(dir, contradicts, true, "RAS", "3D Slicer output. SPACE=LPS"));
  test::expect_error([&] { read_mesh_file(contradicts); },
                     {"contradicts.vtk: FIELD FieldData: SPACE is RAS, but the title line says "
                      "SPACE=LPS"});
  const fs::path other = dir / "other.vtk";
  ASSERT_TRUE(write_with_vtk(dir, other, false, "IJK"));
  test::expect_error([&] { read_mesh_file(other); },
                     {"other.vtk: FIELD FieldData: SPACE is 'IJK', not LPS or RAS"});
}

}  // namespace
}  // namespace imx
