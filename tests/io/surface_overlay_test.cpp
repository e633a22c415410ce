// FreeSurfer surfaces and per-vertex overlays (curv, .annot, .label, GIfTI func/shape/label),
// checked against what nibabel writes and reads back (Debian's /usr/bin/python3).
#include <cmath>
#include <cstring>
#include <limits>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <glm/glm.hpp>

#include "expect_error.hpp"
#include "intermix/error.hpp"
#include "intermix/io.hpp"
#include "io/mesh/freesurfer_surface.hpp"
#include "io/overlay/vertex_overlay.hpp"
#include "nibabel_reference.hpp"
#include "temp_dir.hpp"

namespace imx {
namespace {

using test::read_bytes;

// Written once: surfaces with and without a volume geometry (LIA and oblique), a curvature
// file, an annotation, a label and GIfTI shape and label files, with nibabel's reading of each
// (little-endian float64 arrays, *.ref).
const char* const kSurfaceScript = R"PY(
from collections import OrderedDict
rng = np.random.default_rng(35)
n, f = 500, 900
coords = rng.uniform(-80, 80, (n, 3)).astype(np.float32)
faces = np.array([rng.choice(n, 3, replace=False) for _ in range(f)], dtype=np.int32)

def geometry(cosines, sizes, dims, cras):
    return OrderedDict(head=np.array([2, 0, 20]), valid='1  # volume info valid',
                       filename='orig.mgz', volume=np.array(dims),
                       voxelsize=np.array(sizes, float), xras=np.array(cosines[:, 0], float),
                       yras=np.array(cosines[:, 1], float), zras=np.array(cosines[:, 2], float),
                       cras=np.array(cras, float))

def scanner(path):
    # nibabel's own vox2ras and tkr vox2ras of the geometry: scanner = vox2ras inv(tkr) tkr-RAS
    c, fc, vi = nib.freesurfer.read_geometry(path, read_metadata=True)
    cos = np.column_stack([vi['xras'], vi['yras'], vi['zras']])
    dims = np.array(vi['volume'])
    m = cos * vi['voxelsize']
    affine = np.eye(4)
    affine[:3, :3] = m
    affine[:3, 3] = vi['cras'] - m @ (dims / 2.0)
    img = nib.MGHImage(np.zeros(tuple(dims), np.uint8), affine)
    h = img.header
    t = h.get_vox2ras() @ np.linalg.inv(h.get_vox2ras_tkr())
    out = (t[:3, :3] @ c.T).T + t[:3, 3]
    out.astype('<f8').tofile(path + '.ref')
    fc.astype('<f8').tofile(path + '.faces')

lia = np.array([[-1, 0, 0], [0, 0, 1], [0, -1, 0]], float)
nib.freesurfer.write_geometry('lh.pial', coords, faces,
                              volume_info=geometry(lia, [1, 1, 1], [256, 256, 256], [1.5, -20.25, 12]))
scanner('lh.pial')
a = np.deg2rad(20)
rot = np.array([[np.cos(a), -np.sin(a), 0], [np.sin(a), np.cos(a), 0], [0, 0, 1]])
nib.freesurfer.write_geometry('lh.oblique', coords, faces,
                              volume_info=geometry(rot @ lia, [0.9, 1.1, 1.3], [200, 220, 180], [-4, 7, 30]))
scanner('lh.oblique')
nib.freesurfer.write_geometry('lh.white', coords, faces)
c, fc = nib.freesurfer.read_geometry('lh.white')
c.astype('<f8').tofile('lh.white.ref')

thickness = rng.uniform(0.5, 4.5, n).astype(np.float32)
nib.freesurfer.write_morph_data('lh.thickness', thickness)
nib.freesurfer.read_morph_data('lh.thickness').astype('<f8').tofile('lh.thickness.ref')

labels = rng.integers(-1, 4, n)
ctab = np.array([[25, 5, 25, 0], [220, 20, 10, 0], [20, 220, 60, 0], [60, 20, 220, 0]], np.int32)
names = [b'unknown', b'precentral', b'postcentral', b'insula']
nib.freesurfer.write_annot('lh.aparc.annot', labels, ctab, names)
lab, ct, nm = nib.freesurfer.read_annot('lh.aparc.annot')
lab.astype('<f8').tofile('lh.aparc.annot.ref')
ct.astype('<f8').tofile('lh.aparc.annot.ctab')

members = np.sort(rng.choice(n, 40, replace=False))
with open('lh.BA1.label', 'w') as fo:
    fo.write('#!ascii label  , from subject bert vox2ras=TkReg\n%d\n' % len(members))
    for v in members:
        fo.write('%d  %.3f  %.3f  %.3f 0.0000000000\n' % (v, *coords[v]))
nib.freesurfer.read_label('lh.BA1.label').astype('<f8').tofile('lh.BA1.label.ref')

shape = nib.gifti.GiftiImage(darrays=[nib.gifti.GiftiDataArray(
    thickness, intent='NIFTI_INTENT_SHAPE', datatype='NIFTI_TYPE_FLOAT32')])
nib.save(shape, 'lh.thickness.shape.gii')
func = nib.gifti.GiftiImage(darrays=[
    nib.gifti.GiftiDataArray(rng.normal(0, 2, n).astype(np.float32), intent='NIFTI_INTENT_TTEST',
                             datatype='NIFTI_TYPE_FLOAT32'),
    nib.gifti.GiftiDataArray(rng.normal(5, 2, n).astype(np.float64), intent='NIFTI_INTENT_ZSCORE',
                             datatype='NIFTI_TYPE_FLOAT64', encoding='GIFTI_ENCODING_B64GZ')])
nib.save(func, 'lh.func.gii')
g = nib.load('lh.func.gii')
np.concatenate([d.data.astype('<f8') for d in g.darrays]).tofile('lh.func.gii.ref')
table = nib.gifti.GiftiLabelTable()
for key, name, rgba in [(0, '???', (0, 0, 0, 0)), (1, 'V1', (1, 0, 0, 1)), (2, 'V2', (0, 0.5, 1, 1))]:
    l = nib.gifti.GiftiLabel(key=key, red=rgba[0], green=rgba[1], blue=rgba[2], alpha=rgba[3])
    l.label = name
    table.labels.append(l)
keys = rng.integers(0, 3, n).astype(np.int32)
lab = nib.gifti.GiftiImage(labeltable=table, darrays=[nib.gifti.GiftiDataArray(
    keys, intent='NIFTI_INTENT_LABEL', datatype='NIFTI_TYPE_INT32')])
nib.save(lab, 'lh.label.gii')
nib.load('lh.label.gii').darrays[0].data.astype('<f8').tofile('lh.label.gii.ref')
)PY";

std::vector<double> doubles(const std::filesystem::path& file) {
  const std::string bytes = read_bytes(file);
  std::vector<double> out(bytes.size() / 8);
  std::memcpy(out.data(), bytes.data(), out.size() * 8);
  return out;
}

class SurfaceFiles : public test::NibabelFiles<&kSurfaceScript> {};

TEST_F(SurfaceFiles, TriangleSurfaceIsInScannerRasWithItsGeometry) {
  for (const char* name : {"lh.pial", "lh.oblique"}) {
    const detail::FreeSurferSurface s = detail::read_freesurfer_surface(file(name));
    const std::vector<double> want = doubles(file(std::string(name) + ".ref"));
    const std::vector<double> faces = doubles(file(std::string(name) + ".faces"));
    ASSERT_EQ(s.mesh.positions.size() * 3, want.size()) << name;
    ASSERT_EQ(s.mesh.triangles.size() * 3, faces.size()) << name;
    for (size_t i = 0; i < s.mesh.positions.size(); ++i)
      for (int c = 0; c < 3; ++c)
        ASSERT_NEAR(s.mesh.positions[i][c], want[3 * i + c], 2e-4) << name << " vertex " << i;
    for (size_t t = 0; t < s.mesh.triangles.size(); ++t)
      for (int c = 0; c < 3; ++c) ASSERT_EQ(s.mesh.triangles[t][c], faces[3 * t + c]) << name;
    EXPECT_NE(s.note.find("c_ras"), std::string::npos) << s.note;
  }
}

TEST_F(SurfaceFiles, SurfaceWithoutGeometryKeepsTkrRas) {
  const detail::FreeSurferSurface s = detail::read_freesurfer_surface(file("lh.white"));
  const std::vector<double> want = doubles(file("lh.white.ref"));
  ASSERT_EQ(s.mesh.positions.size() * 3, want.size());
  for (size_t i = 0; i < s.mesh.positions.size(); ++i)
    for (int c = 0; c < 3; ++c) ASSERT_EQ(s.mesh.positions[i][c], want[3 * i + c]);
  EXPECT_NE(s.note.find("without volume geometry"), std::string::npos) << s.note;
}

// read_mesh_file: found by its magic, RAS turned into LPS, and file_vertex leads back to the
// file's vertices through the computed normals' welding and splitting.
TEST_F(SurfaceFiles, MeshFileIsLpsAndMapsBackToFileVertices) {
  const MeshFile m = read_mesh_file(file("lh.pial"));
  const std::vector<double> want = doubles(file("lh.pial.ref"));
  const std::vector<double> faces = doubles(file("lh.pial.faces"));
  EXPECT_EQ(m.info.space, MeshSpace::ras);
  EXPECT_EQ(m.info.space_source, MeshSpaceSource::format);
  EXPECT_EQ(m.info.file_vertices, 500u);
  ASSERT_EQ(m.file_vertex.size(), m.mesh.positions.size());
  for (size_t i = 0; i < m.mesh.positions.size(); ++i) {
    const size_t f = m.file_vertex[i];
    ASSERT_LT(f, 500u);
    EXPECT_NEAR(m.mesh.positions[i].x, -want[3 * f], 2e-4);
    EXPECT_NEAR(m.mesh.positions[i].y, -want[3 * f + 1], 2e-4);
    EXPECT_NEAR(m.mesh.positions[i].z, want[3 * f + 2], 2e-4);
  }
  ASSERT_EQ(m.mesh.triangles.size() * 3, faces.size());
  for (size_t t = 0; t < m.mesh.triangles.size(); ++t)
    for (int c = 0; c < 3; ++c)
      ASSERT_EQ(m.file_vertex[m.mesh.triangles[t][c]], faces[3 * t + c]) << "triangle " << t;
  EXPECT_TRUE(is_mesh_file("lh.pial"));
}

TEST_F(SurfaceFiles, CurvatureValuesAreExact) {
  const detail::VertexOverlay o = detail::read_vertex_overlay(file("lh.thickness"));
  EXPECT_EQ(o.values, doubles(file("lh.thickness.ref")));
  EXPECT_FALSE(o.labels);
  EXPECT_EQ(o.claimed_vertices, 500u);
}

TEST_F(SurfaceFiles, AnnotationGivesTableIndicesAndColours) {
  const detail::VertexOverlay o = detail::read_vertex_overlay(file("lh.aparc.annot"));
  const std::vector<double> want = doubles(file("lh.aparc.annot.ref"));
  const std::vector<double> ctab = doubles(file("lh.aparc.annot.ctab"));
  ASSERT_TRUE(o.labels);
  ASSERT_EQ(o.values.size(), want.size());
  for (size_t v = 0; v < want.size(); ++v) {
    if (want[v] < 0)
      EXPECT_TRUE(std::isnan(o.values[v])) << v;
    else
      EXPECT_EQ(o.values[v], want[v]) << v;
  }
  ASSERT_EQ(o.table.size(), ctab.size() / 5);
  for (size_t k = 0; k < o.table.size(); ++k) {
    EXPECT_EQ(o.table[k].key, static_cast<int64_t>(k));
    for (int c = 0; c < 3; ++c)
      EXPECT_NEAR(o.table[k].rgba[c] * 255.0f, ctab[5 * k + c], 1e-3) << k;
    EXPECT_NEAR(o.table[k].rgba.a, (255.0 - ctab[5 * k + 3]) / 255.0, 1e-6);
  }
  EXPECT_EQ(o.table[1].name, "precentral");
}

TEST_F(SurfaceFiles, LabelNamesItsVertices) {
  const detail::VertexOverlay o = detail::read_vertex_overlay(file("lh.BA1.label"));
  const std::vector<double> want = doubles(file("lh.BA1.label.ref"));
  ASSERT_EQ(o.members.size(), want.size());
  for (size_t i = 0; i < want.size(); ++i) EXPECT_EQ(o.members[i], want[i]);
  const std::vector<double> values = detail::overlay_values(o, 500, "lh.BA1.label");
  for (size_t v = 0; v < values.size(); ++v) {
    const bool member = std::find(want.begin(), want.end(), static_cast<double>(v)) != want.end();
    EXPECT_EQ(std::isnan(values[v]), !member) << v;
  }
  EXPECT_THROW(detail::overlay_values(o, 10, "lh.BA1.label"), Error);
}

TEST_F(SurfaceFiles, GiftiOverlaysReadTheirArraysAndLabelTable) {
  const std::vector<double> func = doubles(file("lh.func.gii.ref"));
  const detail::VertexOverlay first = detail::read_vertex_overlay(file("lh.func.gii"));
  const detail::VertexOverlay second = detail::read_vertex_overlay(file("lh.func.gii"), 1);
  ASSERT_EQ(first.values.size(), 500u);
  ASSERT_EQ(second.values.size(), 500u);
  for (size_t v = 0; v < 500; ++v) {
    EXPECT_EQ(first.values[v], func[v]);
    EXPECT_EQ(second.values[v], func[500 + v]);
  }
  EXPECT_EQ(detail::read_vertex_overlay(file("lh.thickness.shape.gii")).values,
            doubles(file("lh.thickness.ref")));
  const detail::VertexOverlay labels = detail::read_vertex_overlay(file("lh.label.gii"));
  EXPECT_TRUE(labels.labels);
  EXPECT_EQ(labels.values, doubles(file("lh.label.gii.ref")));
  ASSERT_EQ(labels.table.size(), 3u);
  EXPECT_EQ(labels.table[2].name, "V2");
  EXPECT_FLOAT_EQ(labels.table[2].rgba.b, 1.0f);
  EXPECT_FLOAT_EQ(labels.table[2].rgba.g, 0.5f);
  // Still no mesh: the message says why.
  test::expect_error([&] { read_mesh_file(file("lh.func.gii")); }, {"no NIFTI_INTENT_POINTSET"});
  test::expect_error([&] { detail::read_vertex_overlay(file("lh.func.gii"), 2); }, {"no array 2"});
}

// A damaged or foreign file is one clear error, never a crash.
TEST_F(SurfaceFiles, DamagedFilesAreRefused) {
  test::TempDir dir;
  const std::string pial = read_bytes(file("lh.pial"));
  test::write_bytes(dir / "cut.pial", pial.substr(0, 2000));
  test::expect_error([&] { read_mesh_file(dir / "cut.pial"); }, {"the file ends inside"});
  std::string bad_face = pial;
  // The first face's first index (after magic, two lines, counts and 500 vertices) -> 9999.
  const size_t faces_at = pial.find("\n\n") + 2 + 8 + 500 * 12;
  bad_face[faces_at] = 0;
  bad_face[faces_at + 1] = 0;
  bad_face[faces_at + 2] = 0x27;
  bad_face[faces_at + 3] = 0x0F;
  test::write_bytes(dir / "bad.pial", bad_face);
  test::expect_error([&] { read_mesh_file(dir / "bad.pial"); }, {"face 0 uses vertex 9999"});
  test::expect_error([&] { read_mesh_file(file("lh.thickness")); },
                     {"lh.thickness is a surface overlay (FreeSurfer morphometry", "not a mesh"});
  const std::string curv = read_bytes(file("lh.thickness"));
  test::write_bytes(dir / "cut.thickness", curv.substr(0, 100));
  test::expect_error([&] { detail::read_vertex_overlay(dir / "cut.thickness"); },
                     {"the file ends inside"});
  const std::string annot = read_bytes(file("lh.aparc.annot"));
  test::write_bytes(dir / "cut.annot", annot.substr(0, annot.size() - 30));
  test::expect_error([&] { detail::read_vertex_overlay(dir / "cut.annot"); }, {"cut.annot"});
  test::write_bytes(dir / "short.label", "#!ascii label\n3\n1 0 0 0 0\n");
  test::expect_error([&] { detail::read_vertex_overlay(dir / "short.label"); },
                     {"line 2 says 3 vertices, but the file lists 1"});
  test::write_bytes(dir / "plain.txt", "hello");
  test::expect_error([&] { detail::read_vertex_overlay(dir / "plain.txt"); },
                     {"'.txt' is not a surface overlay format intermix reads"});
}

}  // namespace
}  // namespace imx
