// Streamlines from VTK polylines (io/streamlines/vtk_streamlines.hpp): legacy .vtk (ASCII, BINARY,
// the classic and version 5 cell layouts) and XML .vtp (ascii, binary, appended raw and base64,
// zlib or none) written by VTK itself (/usr/bin/python3's vtk), and the shared data's
// tract.FAT_R.vtk, each compared with what VTK's own readers find in the same file; placed as the
// VTK mesh readers place the same file's triangles; damaged files refused with one clear error.
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "expect_error.hpp"
#include "intermix/error.hpp"
#include "intermix/io.hpp"
#include "io/streamlines/vtk_streamlines.hpp"
#include "shared_data.hpp"
#include "temp_dir.hpp"

namespace imx {
namespace {

using test::read_bytes;
using test::write_bytes;

// write(): the fixtures, by VTK's writers; ref(): for a file, NAME.ref, what VTK's readers find,
// little-endian float64: count, arrays (point arrays, then cell arrays), offsets (count + 1),
// points (x, y, z each, as the file has them), each point array's values, each cell array's
// values of the lines; line cells of fewer than 2 points left out, as intermix leaves them.
// Array names go to NAME.names, one a line: "p NAME" or "c NAME".
const char* const kVtkScript = R"PY(
import os, sys
import numpy as np
import vtk
from vtk.util import numpy_support as ns

def ref(path):
    if path.endswith('.vtp'):
        r = vtk.vtkXMLPolyDataReader()
    else:
        r = vtk.vtkPolyDataReader()
        r.ReadAllScalarsOn()
        r.ReadAllFieldsOn()
    r.SetFileName(path)
    r.Update()
    poly = r.GetOutput()
    pts = ns.vtk_to_numpy(poly.GetPoints().GetData()).astype(np.float64)
    parrays, carrays, names = [], [], []
    for data, out, tag in ((poly.GetPointData(), parrays, 'p'), (poly.GetCellData(), carrays, 'c')):
        for i in range(data.GetNumberOfArrays()):
            a = data.GetAbstractArray(i)
            if isinstance(a, vtk.vtkDataArray) and a.GetNumberOfComponents() == 1:
                out.append(ns.vtk_to_numpy(a).astype(np.float64))
                names.append('%s %s' % (tag, a.GetName()))
    first_line = poly.GetNumberOfVerts()
    lines = poly.GetLines()
    lines.InitTraversal()
    ids = vtk.vtkIdList()
    offsets, points, pvals, cvals = [0], [], [[] for _ in parrays], [[] for _ in carrays]
    c = 0
    while lines.GetNextCell(ids):
        idx = [ids.GetId(k) for k in range(ids.GetNumberOfIds())]
        if len(idx) >= 2:
            points.append(pts[idx])
            offsets.append(offsets[-1] + len(idx))
            for a, v in zip(parrays, pvals):
                v.extend(a[idx])
            for a, v in zip(carrays, cvals):
                v.append(a[first_line + c])
        c += 1
    flat = np.vstack(points).ravel() if points else np.zeros(0)
    parts = [np.array([len(offsets) - 1, len(parrays) + len(carrays)]), np.array(offsets), flat]
    parts += [np.array(v) for v in pvals + cvals]
    np.concatenate([p.astype('<f8') for p in parts]).tofile(os.path.basename(path) + '.ref')
    open(os.path.basename(path) + '.names', 'w').write(''.join(n + '\n' for n in names))

rng = np.random.default_rng(5)
lens = [5, 2, 8, 12, 3]  # VTK refuses a line of 1 point
n = sum(lens) + 4
pts = rng.uniform(-80, 80, (n, 3))
perm = rng.permutation(n)
poly = vtk.vtkPolyData()
points = vtk.vtkPoints()
points.SetData(ns.numpy_to_vtk(pts.astype(np.float32), deep=1))
poly.SetPoints(points)
verts, lines, polys = vtk.vtkCellArray(), vtk.vtkCellArray(), vtk.vtkCellArray()
for v in (3, 9):
    verts.InsertNextCell(1)
    verts.InsertCellPoint(v)
k = 0
for length in lens:
    lines.InsertNextCell(length)
    for i in perm[k:k + length]:
        lines.InsertCellPoint(int(i))
    k += length
for tri in ((0, 1, 2), (2, 3, 4)):
    polys.InsertNextCell(3)
    for i in tri:
        polys.InsertCellPoint(i)
poly.SetVerts(verts)
poly.SetLines(lines)
poly.SetPolys(polys)
def array(name, values, components=1):
    a = ns.numpy_to_vtk(np.ascontiguousarray(values), deep=1)
    a.SetName(name)
    return a
poly.GetPointData().SetScalars(array('FA', rng.uniform(0, 1, n).astype(np.float32)))
poly.GetPointData().AddArray(array('curv', rng.normal(0, 1, n)))
poly.GetPointData().AddArray(array('rgb', rng.uniform(0, 1, (n, 3)).astype(np.float32)))
cells = 2 + len(lens) + 2
poly.GetCellData().SetScalars(array('cluster', (np.arange(cells) * 3 + 1).astype(np.int32)))
poly.GetCellData().AddArray(array('weight', rng.uniform(0, 5, cells)))

def legacy(name, binary, version, header):
    w = vtk.vtkPolyDataWriter()
    w.SetFileName(name)
    w.SetInputData(poly)
    w.SetHeader(header)
    w.SetFileVersion(version)
    if binary:
        w.SetFileTypeToBinary()
    else:
        w.SetFileTypeToASCII()
    w.Write()
    ref(name)

legacy('ascii.vtk', False, 42, '3D Slicer output. SPACE=RAS')
legacy('binary.vtk', True, 42, 'vtk output')
legacy('ascii51.vtk', False, 51, 'vtk output SPACE=LPS')
legacy('binary51.vtk', True, 51, '3D Slicer output. SPACE=RAS')

def xml(name, mode, compress=True, encode=True, space=None):
    p = vtk.vtkPolyData()
    p.DeepCopy(poly)
    if space:
        s = vtk.vtkStringArray()
        s.SetName('SPACE')
        s.InsertNextValue(space)
        p.GetFieldData().AddArray(s)
    w = vtk.vtkXMLPolyDataWriter()
    w.SetFileName(name)
    w.SetInputData(p)
    getattr(w, 'SetDataModeTo' + mode)()
    if not compress:
        w.SetCompressorTypeToNone()
    w.SetEncodeAppendedData(encode)
    w.Write()
    ref(name)

xml('ascii.vtp', 'Ascii')
xml('binary.vtp', 'Binary', space='RAS')
xml('binary_raw.vtp', 'Binary', compress=False)
xml('appended.vtp', 'Appended', encode=False, space='LPS')
xml('appended64.vtp', 'Appended', compress=False, encode=True, space='RAS')
for path in sys.argv[1:]:
    ref(path)
)PY";

constexpr const char* kRealFile = "neuro/tracts/tract.FAT_R.vtk";

bool have_vtk() {
  static const bool ok =
      std::system("/usr/bin/python3 -c 'import vtk, numpy' >/dev/null 2>&1") == 0;
  return ok;
}

struct Reference {
  std::vector<double> offsets, points;
  std::vector<std::vector<double>> arrays;
  std::vector<std::string> names;  // "p NAME" or "c NAME"
};

Reference read_reference(const std::filesystem::path& base) {
  const std::string bytes = read_bytes(base.string() + ".ref");
  std::vector<double> d(bytes.size() / 8);
  std::memcpy(d.data(), bytes.data(), d.size() * 8);
  Reference r;
  if (d.size() < 3) {
    ADD_FAILURE() << "no reference for " << base;
    return r;
  }
  const auto count = static_cast<size_t>(d[0]);
  const auto arrays = static_cast<size_t>(d[1]);
  auto at = d.begin() + 2;
  auto take = [&](size_t n) {
    std::vector<double> part(at, at + static_cast<ptrdiff_t>(n));
    at += static_cast<ptrdiff_t>(n);
    return part;
  };
  r.offsets = take(count + 1);
  const auto points = static_cast<size_t>(r.offsets.back());
  r.points = take(3 * points);
  std::string names = read_bytes(base.string() + ".names");
  for (size_t pos = 0; pos < names.size();) {
    const size_t eol = names.find('\n', pos);
    r.names.push_back(names.substr(pos, eol - pos));
    pos = eol + 1;
  }
  for (size_t a = 0; a < arrays; ++a)
    r.arrays.push_back(take(r.names[a][0] == 'p' ? points : count));
  EXPECT_EQ(at, d.end()) << base;
  return r;
}

const StreamlineValues* find_values(const std::vector<StreamlineValues>& v,
                                    const std::string& name) {
  for (const StreamlineValues& s : v)
    if (s.name == name) return &s;
  return nullptr;
}

// `s` holds what VTK read, with x and y negated where the file says SPACE=RAS.
void expect_matches(const Streamlines& s, const Reference& r, bool ras, const std::string& name) {
  ASSERT_EQ(s.offsets.size(), r.offsets.size()) << name;
  for (size_t i = 0; i < r.offsets.size(); ++i)
    ASSERT_EQ(s.offsets[i], static_cast<uint32_t>(r.offsets[i])) << name << " offset " << i;
  ASSERT_EQ(s.points.size() * 3, r.points.size()) << name;
  const float flip = ras ? -1.0f : 1.0f;
  for (size_t i = 0; i < s.points.size(); ++i) {
    EXPECT_NEAR(s.points[i].x, flip * r.points[3 * i], 1e-4) << name << " point " << i;
    EXPECT_NEAR(s.points[i].y, flip * r.points[3 * i + 1], 1e-4) << name << " point " << i;
    EXPECT_NEAR(s.points[i].z, r.points[3 * i + 2], 1e-4) << name << " point " << i;
  }
  size_t point_arrays = 0, cell_arrays = 0;
  for (size_t a = 0; a < r.names.size(); ++a) {
    const bool per_point = r.names[a][0] == 'p';
    const std::string array = r.names[a].substr(2);
    const StreamlineValues* v =
        find_values(per_point ? s.point_values : s.streamline_values, array);
    ASSERT_NE(v, nullptr) << name << ": no array " << r.names[a];
    ASSERT_EQ(v->values.size(), r.arrays[a].size()) << name << " " << array;
    for (size_t i = 0; i < v->values.size(); ++i)
      EXPECT_NEAR(v->values[i], r.arrays[a][i], 1e-5 * (1 + std::abs(r.arrays[a][i])))
          << name << " " << array << " " << i;
    (per_point ? point_arrays : cell_arrays)++;
  }
  EXPECT_EQ(s.point_values.size(), point_arrays) << name;
  EXPECT_EQ(s.streamline_values.size(), cell_arrays) << name;
}

bool contains(const std::vector<std::string>& notes, const std::string& part) {
  for (const std::string& n : notes)
    if (n.find(part) != std::string::npos) return true;
  return false;
}

class VtkStreamlineFiles : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    if (!have_vtk()) return;
    dir_ = new test::TempDir;
    write_bytes(*dir_ / "vtk_lines.py", kVtkScript);
    std::string command = "cd '" + dir_->path().string() + "' && /usr/bin/python3 vtk_lines.py";
    if (std::filesystem::exists(test::shared_data(kRealFile)))
      command += " '" + test::shared_data(kRealFile).string() + "'";
    ok_ = std::system((command + " >vtk.log 2>&1").c_str()) == 0;
  }
  static void TearDownTestSuite() {
    delete dir_;
    dir_ = nullptr;
  }
  void SetUp() override {
    if (!have_vtk()) GTEST_SKIP() << "/usr/bin/python3 with vtk is not available";
    ASSERT_TRUE(ok_) << "the VTK script failed:\n" << read_bytes(*dir_ / "vtk.log");
  }
  static std::filesystem::path file(const std::string& name) { return *dir_ / name; }

 private:
  inline static test::TempDir* dir_ = nullptr;
  inline static bool ok_ = false;
};

TEST_F(VtkStreamlineFiles, RealTractMatchesVtk) {
  SKIP_WITHOUT_SHARED_DATA(kRealFile);
  std::vector<std::string> notes;
  const Streamlines s = detail::read_vtk_streamlines(test::shared_data(kRealFile), notes);
  expect_matches(s, read_reference(file("tract.FAT_R.vtk")), true, kRealFile);
  EXPECT_EQ(s.count(), 5u);
  EXPECT_TRUE(contains(notes, "no SPACE tag")) << ::testing::PrintToString(notes);
}

TEST_F(VtkStreamlineFiles, FilesVtkWroteMatchVtk) {
  struct Case {
    const char* name;
    bool ras;
  };
  for (const Case& c :
       // Untagged files (binary.vtk, ascii.vtp, binary_raw.vtp) are RAS, as tract tools write.
       {Case{"ascii.vtk", true}, Case{"binary.vtk", true}, Case{"ascii51.vtk", false},
        Case{"binary51.vtk", true}, Case{"ascii.vtp", true}, Case{"binary.vtp", true},
        Case{"binary_raw.vtp", true}, Case{"appended.vtp", false}, Case{"appended64.vtp", true}}) {
    std::vector<std::string> notes;
    const Streamlines s = detail::read_vtk_streamlines(file(c.name), notes);
    expect_matches(s, read_reference(file(c.name)), c.ras, c.name);
    EXPECT_EQ(s.count(), 5u) << c.name;
    EXPECT_TRUE(find_values(s.point_values, "FA") && find_values(s.point_values, "curv") &&
                find_values(s.streamline_values, "cluster") &&
                find_values(s.streamline_values, "weight"))
        << c.name;
    EXPECT_TRUE(contains(notes, "array 'rgb' left unread")) << c.name;
    EXPECT_TRUE(contains(notes, c.ras ? "x and y negated" : "LPS")) << c.name;
  }
}

// The streamlines land where the mesh reader puts the same file's vertices (the triangles'
// corners), whatever space the file names (untagged ones differ: RAS for tracts, LPS for meshes).
TEST_F(VtkStreamlineFiles, LandWhereTheSameFilesTrianglesLand) {
  for (const char* name : {"ascii.vtk", "ascii51.vtk", "binary.vtp", "appended.vtp"}) {
    std::vector<std::string> notes;
    const Streamlines s = detail::read_vtk_streamlines(file(name), notes);
    const MeshFile mesh = read_mesh_file(file(name));
    ASSERT_FALSE(mesh.mesh.triangles.empty()) << name;
    // A streamline point is the same file point as a mesh vertex where |x| and z agree (random
    // floats): then the two must be placed alike, to the bit.
    size_t compared = 0;
    for (size_t v = 0; v < mesh.mesh.positions.size(); ++v) {
      const glm::vec3 placed = mesh.mesh.positions[v];
      for (size_t i = 0; i < s.points.size(); ++i) {
        const bool same_file_point =
            s.points[i].z == placed.z && std::abs(s.points[i].x) == std::abs(placed.x);
        if (!same_file_point) continue;
        EXPECT_EQ(s.points[i], placed) << name << " mesh vertex " << v;
        ++compared;
      }
    }
    EXPECT_GT(compared, 0u) << name;
  }
}

TEST_F(VtkStreamlineFiles, TheMeshReaderStillRefusesLinesOnly) {
  std::vector<std::string> notes;
  const std::filesystem::path lines_only = file("lines_only.vtk");
  test::write_bytes(lines_only,
                    "# vtk DataFile Version 3.0\nlines\nASCII\nDATASET POLYDATA\nPOINTS 3 float\n"
                    "0 0 0 1 1 1 2 2 2\nLINES 2 6\n3 0 1 2\n1 1\n");
  test::expect_error([&] { read_mesh_file(lines_only); }, {"no triangles"});
  const Streamlines s = detail::read_vtk_streamlines(lines_only, notes);
  ASSERT_EQ(s.count(), 1u);
  EXPECT_EQ(s.points[2], glm::vec3(-2.0f, -2.0f, 2.0f));  // untagged: RAS, turned to LPS
  EXPECT_TRUE(contains(notes, "1 line cells of fewer than 2 points left out"));
}

std::string legacy_ascii(const std::string& body) {
  return "# vtk DataFile Version 3.0\ntest\nASCII\nDATASET POLYDATA\nPOINTS 3 float\n"
         "0 0 0 1 1 1 2 2 2\n" +
         body;
}

std::string vtp(const std::string& piece_attributes, const std::string& connectivity,
                const std::string& offsets) {
  return "<?xml version=\"1.0\"?>\n<VTKFile type=\"PolyData\" version=\"0.1\">\n<PolyData>\n"
         "<Piece NumberOfPoints=\"3\" " +
         piece_attributes +
         ">\n<Points><DataArray type=\"Float32\" NumberOfComponents=\"3\" format=\"ascii\">"
         "0 0 0 1 1 1 2 2 2</DataArray></Points>\n<Lines>"
         "<DataArray type=\"Int64\" Name=\"connectivity\" format=\"ascii\">" +
         connectivity + "</DataArray><DataArray type=\"Int64\" Name=\"offsets\" format=\"ascii\">" +
         offsets + "</DataArray></Lines>\n</Piece>\n</PolyData>\n</VTKFile>\n";
}

TEST(VtkStreamlines, RefusesDamagedFiles) {
  test::TempDir dir;
  std::vector<std::string> notes;
  auto refused = [&](const std::string& name, const std::string& bytes,
                     std::initializer_list<std::string> fragments) {
    const std::filesystem::path f = dir.write(name, bytes);
    std::vector<std::string> parts(fragments);
    parts.push_back(f.string());
    const std::string message = test::error_of([&] { detail::read_vtk_streamlines(f, notes); });
    for (const std::string& part : parts)
      EXPECT_NE(message.find(part), std::string::npos) << name << ": " << message;
  };
  refused("past.vtk", legacy_ascii("LINES 1 4\n3 0 1 7\n"),
          {"line cell 0 uses point 7, but the file has 3 points"});
  refused("negative.vtk", legacy_ascii("LINES 1 3\n2 0 -1\n"), {"line cell 0 uses point -1"});
  refused("cells_lie.vtk", legacy_ascii("LINES 5 8\n3 0 1 2\n3 0 1 2\n"),
          {"LINES", "the data ends inside cell 2 of 5"});
  refused("size_lies.vtk", legacy_ascii("LINES 1 100\n3 0 1 2\n"), {"LINES", "100 values"});
  refused("cell_claims.vtk", legacy_ascii("LINES 1 3\n7 0 1\n"), {"cell 0 claims 7 points"});
  refused("cell_data_lies.vtk",
          legacy_ascii("LINES 1 4\n3 0 1 2\nCELL_DATA 4\nSCALARS c float 1\nLOOKUP_TABLE "
                       "default\n1 2 3 4\n"),
          {"CELL_DATA array 'c' holds 4 tuples, but the file has 1 cells"});
  refused("truncated_binary.vtk",
          "# vtk DataFile Version 3.0\ntest\nBINARY\nDATASET POLYDATA\nPOINTS 3 float\n" +
              std::string(36, '\0') + "\nLINES 2 8\n" + std::string(12, '\0'),
          {"LINES", "8 values"});
  refused("past.vtp", vtp("NumberOfLines=\"1\"", "0 1 9", "3"),
          {"Lines cell 0: point index 9 is not one of the piece's 3 points"});
  refused("offsets_past.vtp", vtp("NumberOfLines=\"1\"", "0 1 2", "5"),
          {"cell 0 ends at offset 5, outside 0..3"});
  refused("count_lies.vtp", vtp("NumberOfLines=\"4\"", "0 1 2", "3"), {"1 offsets for 4 cells"});
  refused("bad_count.vtp", vtp("NumberOfLines=\"many\"", "0 1 2", "3"),
          {"NumberOfLines 'many' is not a count"});
  refused("no_lines.vtp",
          "<?xml version=\"1.0\"?>\n<VTKFile type=\"PolyData\"><PolyData><Piece "
          "NumberOfPoints=\"0\" NumberOfLines=\"2\"></Piece></PolyData></VTKFile>\n",
          {"<Lines> lacks its connectivity or offsets array"});
  refused("neither.vtk", "solid x\nendsolid\n", {"neither legacy VTK"});
}

}  // namespace
}  // namespace imx
