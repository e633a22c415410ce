// VTK polydata meshes: legacy .vtk (ASCII, BINARY, version 5 cells) and XML .vtp (ascii, base64,
// appended raw and base64, zlib), written by a Python script from the format's documentation,
// which also computes the triangles the cells make; point data become MeshFile::point_data.
#include <cmath>
#include <cstring>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "expect_error.hpp"
#include "intermix/error.hpp"
#include "intermix/io.hpp"
#include "io/mesh/polydata.hpp"
#include "nibabel_reference.hpp"
#include "temp_dir.hpp"

namespace imx {
namespace {

using test::read_bytes;

const char* const kPolyDataScript = R"PY(
import base64, struct, zlib
rng = np.random.default_rng(7)
n = 60
pts = rng.uniform(-50, 50, (n, 3)).astype(np.float32)
thick = rng.uniform(1, 4, n).astype(np.float32)
nrm = rng.normal(0, 1, (n, 3))
nrm = (nrm / np.linalg.norm(nrm, axis=1)[:, None]).astype(np.float32)
polys = [list(rng.choice(n, 3, replace=False)) for _ in range(40)] + [[0, 1, 2, 3], [5, 6, 7, 8, 9]]
strips = [[10, 11, 12, 13, 14, 15], [20, 21, 22]]
tris = []
for c in polys:
    for k in range(1, len(c) - 1):
        tris.append([c[0], c[k], c[k + 1]])
for c in strips:
    for k in range(len(c) - 2):
        a, b, d = c[k], c[k + 1], c[k + 2]
        tris.append([b, a, d] if k % 2 else [a, b, d])
np.array(tris, '<f8').tofile('tris.ref')
pts.astype('<f8').tofile('points.ref')
thick.astype('<f8').tofile('thick.ref')
nrm.astype('<f8').tofile('normals.ref')

def legacy(name, binary, v5, title):
    out = [b'# vtk DataFile Version %s\n' % (b'5.1' if v5 else b'4.2'), title + b'\n',
           b'BINARY\n' if binary else b'ASCII\n', b'DATASET POLYDATA\n']
    def arr(values, fmt):
        if binary:
            return np.asarray(values).astype(fmt).tobytes() + b'\n'
        return (' '.join(repr(float(x)) if fmt[1] == 'f' else str(int(x))
                         for x in np.asarray(values).ravel()) + '\n').encode()
    out.append(b'POINTS %d float\n' % n)
    out.append(arr(pts, '>f4'))
    for key, cells in ((b'POLYGONS', polys), (b'TRIANGLE_STRIPS', strips)):
        if v5:
            offs = np.cumsum([0] + [len(c) for c in cells])
            conn = [i for c in cells for i in c]
            out.append(b'%s %d %d\n' % (key, len(offs), len(conn)))
            out.append(b'OFFSETS vtktypeint64\n' + arr(offs, '>i8'))
            out.append(b'CONNECTIVITY vtktypeint64\n' + arr(conn, '>i8'))
        else:
            flat = [x for c in cells for x in [len(c)] + list(c)]
            out.append(b'%s %d %d\n' % (key, len(cells), len(flat)))
            out.append(arr(flat, '>i4'))
    out.append(b'CELL_DATA %d\nSCALARS cellid int 1\nLOOKUP_TABLE default\n' % (len(polys) + len(strips)))
    out.append(arr(range(len(polys) + len(strips)), '>i4'))
    out.append(b'POINT_DATA %d\nSCALARS thickness float 1\nLOOKUP_TABLE default\n' % n)
    out.append(arr(thick, '>f4'))
    out.append(b'NORMALS Normals float\n' + arr(nrm, '>f4'))
    out.append(b'FIELD FieldData 1\nsulc 1 %d double\n' % n + arr(thick * 2, '>f8'))
    open(name, 'wb').write(b''.join(out))

legacy('ascii.vtk', False, False, b'3D Slicer output. SPACE=RAS')
legacy('binary.vtk', True, False, b'3D Slicer output. SPACE=LPS')
legacy('v5.vtk', False, True, b'vtk output')

def b64(data):
    return base64.b64encode(data).decode()

def vtp(name, mode, header='UInt32', compress=False):
    hfmt = '<I' if header == 'UInt32' else '<Q'
    appended = b''
    def array(values, vtype, npfmt, name=None, comps=1, separate=False):
        nonlocal appended
        raw = np.asarray(values).astype(npfmt).tobytes()
        attrs = 'type="%s"%s NumberOfComponents="%d"' % (vtype, ' Name="%s"' % name if name else '', comps)
        if mode == 'ascii':
            text = ' '.join(str(x) for x in np.asarray(values).ravel())
            return '<DataArray %s format="ascii">%s</DataArray>' % (attrs, text)
        if compress:
            bs = 64
            blocks = [raw[i:i + bs] for i in range(0, len(raw), bs)] or [b'']
            packed = [zlib.compress(b) for b in blocks]
            last = len(raw) - bs * (len(blocks) - 1)
            head = struct.pack('<' + hfmt[1] * (3 + len(blocks)), len(blocks), bs,
                               0 if last == bs else last, *[len(p) for p in packed])
            body = b''.join(packed)
        else:
            head = struct.pack(hfmt, len(raw))
            body = raw
        if mode == 'binary':
            text = b64(head) + b64(body) if separate else b64(head + body)
            return '<DataArray %s format="binary">%s</DataArray>' % (attrs, text)
        offset = len(appended)
        appended += (head + body) if mode == 'raw' else (b64(head) + b64(body)).encode()
        return '<DataArray %s format="appended" offset="%d"/>' % (attrs, offset)
    offs = np.cumsum([len(c) for c in polys])
    conn = [i for c in polys for i in c]
    soffs = np.cumsum([len(c) for c in strips])
    sconn = [i for c in strips for i in c]
    space = array(np.frombuffer(b'RAS\0', np.uint8), 'String', '<u1', 'SPACE')
    xml = ['<?xml version="1.0"?>',
           '<VTKFile type="PolyData" version="1.0" byte_order="LittleEndian" header_type="%s"%s>'
           % (header, ' compressor="vtkZLibDataCompressor"' if compress else ''),
           '<PolyData>', '<FieldData>', space.replace('NumberOfComponents="1"', 'NumberOfTuples="1"'),
           '</FieldData>',
           '<Piece NumberOfPoints="%d" NumberOfVerts="0" NumberOfLines="0" NumberOfStrips="%d" NumberOfPolys="%d">'
           % (n, len(strips), len(polys)),
           '<PointData Scalars="thickness" Normals="Normals">',
           array(thick, 'Float32', '<f4', 'thickness', separate=True),
           array(nrm, 'Float32', '<f4', 'Normals', 3),
           '</PointData>', '<Points>', array(pts, 'Float32', '<f4', 'Points', 3), '</Points>',
           '<Polys>', array(conn, 'Int64', '<i8', 'connectivity'),
           array(offs, 'Int64', '<i8', 'offsets'), '</Polys>',
           '<Strips>', array(sconn, 'Int32', '<i4', 'connectivity'),
           array(soffs, 'Int32', '<i4', 'offsets'), '</Strips>',
           '</Piece>', '</PolyData>']
    out = ('\n'.join(xml) + '\n').encode()
    if mode in ('raw', 'base64'):
        out += ('<AppendedData encoding="%s">\n_' % mode).encode() + appended + b'\n</AppendedData>\n'
    out += b'</VTKFile>\n'
    open(name, 'wb').write(out)

vtp('ascii.vtp', 'ascii')
vtp('binary.vtp', 'binary')
vtp('binary64z.vtp', 'binary', 'UInt64', True)
vtp('raw.vtp', 'raw')
vtp('rawz.vtp', 'raw', 'UInt64', True)
vtp('base64.vtp', 'base64', 'UInt32', True)
)PY";

std::vector<double> doubles(const std::filesystem::path& file) {
  const std::string bytes = read_bytes(file);
  std::vector<double> out(bytes.size() / 8);
  std::memcpy(out.data(), bytes.data(), out.size() * 8);
  return out;
}

class PolyDataFiles : public test::NibabelFiles<&kPolyDataScript> {
 protected:
  // The reader's polydata equals the script's points, triangles, thickness and normals.
  void expect_reference(const detail::PolyDataFile& p, const std::string& name) {
    const std::vector<double> points = doubles(file("points.ref"));
    const std::vector<double> tris = doubles(file("tris.ref"));
    const std::vector<double> thick = doubles(file("thick.ref"));
    const std::vector<double> normals = doubles(file("normals.ref"));
    ASSERT_EQ(p.mesh.positions.size() * 3, points.size()) << name;
    for (size_t i = 0; i < p.mesh.positions.size(); ++i)
      for (int c = 0; c < 3; ++c)
        ASSERT_EQ(p.mesh.positions[i][c], static_cast<float>(points[3 * i + c])) << name;
    ASSERT_EQ(p.mesh.triangles.size() * 3, tris.size()) << name;
    for (size_t t = 0; t < p.mesh.triangles.size(); ++t)
      for (int c = 0; c < 3; ++c) ASSERT_EQ(p.mesh.triangles[t][c], tris[3 * t + c]) << name;
    ASSERT_EQ(p.mesh.normals.size() * 3, normals.size()) << name;
    for (size_t i = 0; i < p.mesh.normals.size(); ++i)
      for (int c = 0; c < 3; ++c)
        ASSERT_NEAR(p.mesh.normals[i][c], normals[3 * i + c], 1e-6) << name;
    const MeshPointData* t = nullptr;
    for (const MeshPointData& d : p.point_data)
      if (d.name == "thickness") t = &d;
    ASSERT_NE(t, nullptr) << name;
    EXPECT_EQ(t->components, 1);
    ASSERT_EQ(t->values.size(), thick.size()) << name;
    for (size_t i = 0; i < thick.size(); ++i)
      EXPECT_EQ(static_cast<float>(t->values[i]), static_cast<float>(thick[i])) << name;
  }
};

TEST_F(PolyDataFiles, LegacyAsciiBinaryAndVersion5) {
  for (const char* name : {"ascii.vtk", "binary.vtk", "v5.vtk"}) {
    const detail::PolyDataFile p = detail::read_vtk_legacy(file(name));
    expect_reference(p, name);
    bool sulc = false;
    for (const MeshPointData& d : p.point_data) sulc = sulc || d.name == "sulc";
    EXPECT_TRUE(sulc) << name << ": the FIELD array of point data";
  }
  EXPECT_EQ(detail::read_vtk_legacy(file("ascii.vtk")).space, MeshSpace::ras);
  EXPECT_EQ(detail::read_vtk_legacy(file("binary.vtk")).space, MeshSpace::lps);
  EXPECT_FALSE(detail::read_vtk_legacy(file("v5.vtk")).space.has_value());
}

TEST_F(PolyDataFiles, XmlEveryEncoding) {
  for (const char* name :
       {"ascii.vtp", "binary.vtp", "binary64z.vtp", "raw.vtp", "rawz.vtp", "base64.vtp"}) {
    const detail::PolyDataFile p = detail::read_vtp(file(name));
    expect_reference(p, name);
    EXPECT_EQ(p.space, MeshSpace::ras) << name << ": Slicer's SPACE field";
  }
}

// Through read_mesh_file: SPACE=RAS is converted, the file's normals are kept (no welding) and
// the point data come along.
TEST_F(PolyDataFiles, MeshFileConvertsRasAndKeepsPointData) {
  const MeshFile m = read_mesh_file(file("rawz.vtp"));
  const std::vector<double> points = doubles(file("points.ref"));
  EXPECT_EQ(m.info.space, MeshSpace::ras);
  EXPECT_TRUE(m.info.file_normals);
  ASSERT_EQ(m.mesh.positions.size(), 60u);
  EXPECT_FLOAT_EQ(m.mesh.positions[7].x, -static_cast<float>(points[21]));
  EXPECT_FLOAT_EQ(m.mesh.positions[7].z, static_cast<float>(points[23]));
  EXPECT_EQ(m.file_vertex[7], 7u);
  ASSERT_EQ(m.point_data.size(), 1u);
  EXPECT_EQ(m.point_data[0].name, "thickness");
  EXPECT_TRUE(is_mesh_file("model.vtk"));
  EXPECT_TRUE(is_mesh_file("model.vtp"));
}

TEST_F(PolyDataFiles, DamagedFilesAreRefused) {
  test::TempDir dir;
  const std::string binary = read_bytes(file("binary.vtk"));
  test::write_bytes(dir / "cut.vtk", binary.substr(0, 700));
  test::expect_error([&] { read_mesh_file(dir / "cut.vtk"); }, {"cut.vtk", "rest of the file"});
  std::string ascii = read_bytes(file("ascii.vtk"));
  ascii.replace(ascii.find("POLYGONS 42"), 11, "POLYGONS 43");
  test::write_bytes(dir / "count.vtk", ascii);
  test::expect_error([&] { read_mesh_file(dir / "count.vtk"); }, {"POLYGONS"});
  test::write_bytes(dir / "grid.vtk",
                    "# vtk DataFile Version 3.0\nx\nASCII\nDATASET STRUCTURED_POINTS\n");
  test::expect_error([&] { read_mesh_file(dir / "grid.vtk"); }, {"reads POLYDATA"});
  std::string rawz = read_bytes(file("rawz.vtp"));
  test::write_bytes(dir / "cut.vtp", rawz.substr(0, rawz.size() - 200));
  test::expect_error([&] { read_mesh_file(dir / "cut.vtp"); }, {"cut.vtp"});
  std::string lz4 = read_bytes(file("rawz.vtp"));
  lz4.replace(lz4.find("vtkZLibDataCompressor"), 21, "vtkLZ4DataCompressor");
  test::write_bytes(dir / "lz4.vtp", lz4);
  test::expect_error([&] { read_mesh_file(dir / "lz4.vtp"); }, {"vtkLZ4DataCompressor"});
  std::string corrupt = read_bytes(file("ascii.vtp"));
  corrupt.replace(corrupt.find("NumberOfPoints=\"60\""), 19, "NumberOfPoints=\"61\"");
  test::write_bytes(dir / "points.vtp", corrupt);
  test::expect_error([&] { read_mesh_file(dir / "points.vtp"); }, {"NumberOfPoints 61"});
  // A count whose product with 3 (or 48 bytes) wraps around: refused by the count, not by the
  // allocator.
  test::write_bytes(dir / "huge.vtk",
                    "# vtk DataFile Version 3.0\nx\nASCII\nDATASET POLYDATA\n"
                    "POINTS 6148914691236517206 float\n0 0 0 1 1 1\n");
  test::expect_error([&] { read_mesh_file(dir / "huge.vtk"); },
                     {"huge.vtk", "count 6148914691236517206 is more than intermix reads"});
}

}  // namespace
}  // namespace imx
