// CIFTI-2 dense files (dscalar, dlabel, dtseries) mapped onto surface vertices, checked against
// nibabel.cifti2 (Debian's /usr/bin/python3): the real fs_LR 32k curvature file of the shared
// data and small files nibabel writes here, plus copies of those whose counts lie.
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "expect_error.hpp"
#include "intermix/error.hpp"
#include "intermix/io.hpp"
#include "io/overlay/cifti.hpp"
#include "io/overlay/vertex_overlay.hpp"
#include "nibabel_reference.hpp"
#include "shared_data.hpp"
#include "temp_dir.hpp"

namespace imx {
namespace {

using test::read_bytes;
using test::write_bytes;

// ref_cifti(path) writes path + ".txt": what nibabel.cifti2 reads, one fact a line: "maps N",
// "structure NAME OFFSET COUNT VERTICES" and "vertices ..." for each surface model, "values NAME
// MAP v0 v1 ..." (every vertex of the surface, nan where the file has none) and "label MAP KEY
// R G B A NAME".
const char* const kCiftiScript = R"PY(
from nibabel import cifti2

def ref_cifti(path, out=None):
    img = nib.load(path)
    data = np.asarray(img.get_fdata(), dtype=np.float64)
    labels, models = img.header.get_axis(0), img.header.get_axis(1)
    lines = ['maps %d' % data.shape[0]]
    for name, sl, bm in models.iter_structures():
        if not bm.surface_mask.all():
            continue
        n = bm.nvertices[name]
        start = sl.start or 0
        lines.append('structure %s %d %d %d' % (name, start, len(bm), n))
        lines.append('vertices ' + ' '.join(str(v) for v in bm.vertex))
        for m in range(data.shape[0]):
            v = np.full(n, np.nan)
            v[bm.vertex] = data[m, start:start + len(bm)]
            lines.append('values %s %d ' % (name, m) + ' '.join(repr(float(x)) for x in v))
    if isinstance(labels, cifti2.LabelAxis):
        for m, table in enumerate(labels.label):
            for key, (label, rgba) in table.items():
                lines.append('label %d %d %r %r %r %r %s' % ((m, key) + tuple(rgba) + (label,)))
    open((out or path) + '.txt', 'w').write('\n'.join(lines) + '\n')

rng = np.random.default_rng(7)
left = cifti2.BrainModelAxis.from_surface(np.array([0, 2, 3, 5, 7, 8]), 10, 'CortexLeft')
right = cifti2.BrainModelAxis.from_surface(np.array([9, 1, 4, 2]), 10, 'CortexRight')
mask = np.zeros((3, 3, 3), bool)
mask[0, 1, 2] = mask[2, 2, 0] = mask[1, 0, 1] = True
voxels = cifti2.BrainModelAxis.from_mask(mask, 'ThalamusLeft', np.eye(4))
models = left + right + voxels

def save(axes, data, intent, name):
    img = cifti2.Cifti2Image(data, header=axes)
    img.nifti_header.set_intent(intent)
    img.to_filename(name)
    ref_cifti(name)

save((cifti2.ScalarAxis(['first map', 'second']), models),
     rng.normal(size=(2, len(models))).astype(np.float32), 'ConnDenseScalar', 'lr.dscalar.nii')
tables = [{0: ('???', (0.0, 0.0, 0.0, 0.0)), 1: ('V1', (1.0, 0.0, 0.0, 1.0)),
           2: ('V2', (0.0, 0.5, 1.0, 1.0))},
          {0: ('???', (0.0, 0.0, 0.0, 0.0)), 7: ('MT', (0.25, 0.75, 0.125, 0.5))}]
keys = np.array([rng.choice([0, 1, 2], len(models)), rng.choice([0, 7], len(models))])
save((cifti2.LabelAxis(['areas', 'motion'], tables), models), keys.astype(np.float32),
     'ConnDenseLabel', 'lr.dlabel.nii')
save((cifti2.SeriesAxis(0.0, 0.72, 5, 'second'), left + right),
     rng.normal(size=(5, 10)).astype(np.float32), 'ConnDenseSeries', 'lr.dtseries.nii')
# Structures of different vertex counts, for the choice by count.
wide = cifti2.BrainModelAxis.from_surface(np.array([0, 11, 4]), 12, 'CortexRight')
save((cifti2.ScalarAxis(['m']), left + wide), rng.normal(size=(1, 9)).astype(np.float32),
     'ConnDenseScalar', 'counts.dscalar.nii')
parcels = cifti2.ParcelsAxis.from_brain_models([('V1', left), ('MT', right)])
img = cifti2.Cifti2Image(np.ones((1, 2), np.float32), header=(cifti2.ScalarAxis(['p']), parcels))
img.nifti_header.set_intent('ConnParcelScalr')
img.to_filename('lr.pscalar.nii')
nib.save(nib.Nifti2Image(np.ones((2, 3, 4), np.float32), np.eye(4)), 'plain.nii')

# Surfaces of 10 vertices: one that says it is the right cortex, one that says nothing.
def surface(name, structure, n=10):
    coords = rng.uniform(-50, 50, (n, 3)).astype(np.float32)
    faces = np.array([[0, i, i + 1] for i in range(1, n - 1)], np.int32)
    meta = {'AnatomicalStructurePrimary': structure} if structure else {}
    g = nib.gifti.GiftiImage(darrays=[
        nib.gifti.GiftiDataArray(coords, intent='NIFTI_INTENT_POINTSET', datatype='NIFTI_TYPE_FLOAT32',
                                 meta=nib.gifti.GiftiMetaData(meta)),
        nib.gifti.GiftiDataArray(faces, intent='NIFTI_INTENT_TRIANGLE', datatype='NIFTI_TYPE_INT32')])
    nib.save(g, name)
surface('cortex.surf.gii', 'CortexRight')
surface('plain.surf.gii', None)
surface('sub.L.white.surf.gii', None)
surface('twelve.surf.gii', None, 12)
)PY";

class Cifti : public test::NibabelFiles<&kCiftiScript> {};

// What ref_cifti wrote.
struct CiftiReference {
  struct Structure {
    int64_t offset = 0, count = 0, vertices = 0;
    std::vector<uint32_t> indices;
    std::vector<std::vector<double>> values;  // per map, per vertex
  };
  int64_t maps = 0;
  std::map<std::string, Structure> structures;
  std::vector<std::vector<detail::OverlayLabel>> labels;  // per map
};

CiftiReference read_cifti_reference(const std::filesystem::path& file) {
  CiftiReference r;
  std::istringstream lines(read_bytes(file.string() + ".txt"));
  std::string line;
  while (std::getline(lines, line)) {
    std::istringstream in(line);
    std::string what, name;
    in >> what;
    if (what == "maps") {
      in >> r.maps;
    } else if (what == "structure") {
      in >> name;
      in >> r.structures[name].offset >> r.structures[name].count >> r.structures[name].vertices;
    } else if (what == "vertices") {
      CiftiReference::Structure& s = std::prev(r.structures.end())->second;
      for (uint32_t v; in >> v;) s.indices.push_back(v);
    } else if (what == "values") {
      size_t map = 0;
      in >> name >> map;
      std::vector<std::vector<double>>& values = r.structures[name].values;
      values.resize(map + 1);
      for (std::string word; in >> word;) values[map].push_back(std::strtod(word.c_str(), nullptr));
    } else if (what == "label") {
      size_t map = 0;
      detail::OverlayLabel l;
      in >> map >> l.key >> l.rgba.r >> l.rgba.g >> l.rgba.b >> l.rgba.a;
      std::getline(in >> std::ws, l.name);
      r.labels.resize(std::max(r.labels.size(), map + 1));
      r.labels[map].push_back(l);
    }
  }
  EXPECT_GT(r.maps, 0) << "no nibabel reference for " << file;
  return r;
}

// Every structure and every map of `file` as read_cifti and cifti_overlay read them equals
// nibabel's, NaN where nibabel has no value.
void expect_like_nibabel(const std::filesystem::path& file) {
  const CiftiReference ref = read_cifti_reference(file);
  const detail::CiftiFile c = detail::read_cifti(file);
  EXPECT_EQ(c.maps, ref.maps) << file;
  size_t surfaces = 0;
  for (const detail::CiftiBrainModel& m : c.models) {
    if (!m.surface) continue;
    ++surfaces;
    ASSERT_TRUE(ref.structures.contains(m.structure)) << file << ": " << m.structure;
    const CiftiReference::Structure& s = ref.structures.at(m.structure);
    EXPECT_EQ(m.offset, s.offset) << m.structure;
    EXPECT_EQ(m.count, s.count) << m.structure;
    EXPECT_EQ(m.surface_vertices, s.vertices) << m.structure;
    EXPECT_EQ(m.vertices, s.indices) << m.structure;
    for (int64_t map = 0; map < c.maps; ++map) {
      const detail::VertexOverlay o = detail::cifti_overlay(c, m.structure, map, file.string());
      EXPECT_EQ(o.claimed_vertices, static_cast<uint64_t>(s.vertices));
      const std::vector<double>& want = s.values.at(static_cast<size_t>(map));
      ASSERT_EQ(o.values.size(), want.size()) << m.structure << " map " << map;
      int wrong = 0;
      for (size_t v = 0; v < want.size(); ++v) {
        const bool same = std::isnan(want[v]) ? std::isnan(o.values[v]) : o.values[v] == want[v];
        if (!same && wrong++ < 5)
          ADD_FAILURE() << file << " " << m.structure << " map " << map << " vertex " << v << ": "
                        << o.values[v] << ", nibabel " << want[v];
      }
      EXPECT_EQ(wrong, 0) << m.structure << " map " << map;
      EXPECT_EQ(o.labels, !ref.labels.empty());
    }
  }
  EXPECT_EQ(surfaces, ref.structures.size()) << file;
}

TEST(CiftiReal, Fs32kCurvatureIsNibabelsOnEveryVertexOfBothHemispheres) {
  SKIP_WITHOUT_SHARED_DATA("neuro/surfaces/fs_LR.32k.LR.curvature.dscalar.nii");
  if (!test::have_nibabel()) GTEST_SKIP() << "/usr/bin/python3 with nibabel is not available";
  const std::filesystem::path real =
      test::shared_data("neuro/surfaces/fs_LR.32k.LR.curvature.dscalar.nii");
  test::TempDir dir;
  ASSERT_TRUE(test::run_nibabel(
      dir, std::string(kCiftiScript).substr(0, std::string(kCiftiScript).find("rng =")) +
               "ref_cifti('" + real.string() + "', 'real')\n"));
  // The reference lies in the temporary folder: read it through a link named like it.
  std::filesystem::create_symlink(real, dir / "real");
  expect_like_nibabel(dir / "real");
  const detail::CiftiFile c = detail::read_cifti(dir / "real");
  EXPECT_EQ(c.kind, detail::CiftiMapKind::scalars);
  ASSERT_EQ(c.map_names.size(), 1u);
  EXPECT_EQ(c.map_names[0], "HCP_Q1-Q6_R440_curvature");
  EXPECT_TRUE(detail::is_cifti(real));
  // The left surface is the left cortex by its GIfTI metadata (both have 32492 vertices).
  SKIP_WITHOUT_SHARED_DATA("neuro/surfaces/fs_LR.32k.L.inflated.surf.gii");
  const std::filesystem::path surface =
      test::shared_data("neuro/surfaces/fs_LR.32k.L.inflated.surf.gii");
  const size_t n = read_mesh_file(surface).info.file_vertices;
  EXPECT_EQ(detail::cifti_structure_of_surface(c, surface, n), "CIFTI_STRUCTURE_CORTEX_LEFT");
  // As a volume it is refused, not read as 1x1x1 voxels of 59412 frames.
  test::expect_error([&] { read_volume(real); },
                     {"is a CIFTI-2 file of surface data", "give it after its surfaces"});
  test::expect_error([&] { read_volume_header(real); }, {"CIFTI-2 file of surface data"});
}

TEST_F(Cifti, ScalarsLabelsAndSeriesAreNibabelsValuesOnEachStructure) {
  for (const char* name :
       {"lr.dscalar.nii", "lr.dlabel.nii", "lr.dtseries.nii", "counts.dscalar.nii"})
    expect_like_nibabel(file(name));
  const detail::CiftiFile scalars = detail::read_cifti(file("lr.dscalar.nii"));
  EXPECT_EQ(scalars.map_names, (std::vector<std::string>{"first map", "second"}));
  // The voxel model (thalamus) is kept as brainordinates but has no surface.
  ASSERT_EQ(scalars.models.size(), 3u);
  EXPECT_FALSE(scalars.models[2].surface);
  EXPECT_EQ(scalars.brainordinates, 13);
  test::expect_error(
      [&] { detail::cifti_overlay(scalars, "CIFTI_STRUCTURE_THALAMUS_LEFT", 0, "x"); },
      {"no surface structure THALAMUS_LEFT", "CORTEX_LEFT (10 vertices)", "CORTEX_RIGHT"});
  test::expect_error([&] { detail::cifti_overlay(scalars, "CORTEX_LEFT", 2, "x"); },
                     {"map 2 asked for", "2 maps (0 to 1)"});
  // Short and lower-case structure names find the same model.
  const std::vector<double>
      shortly = detail::cifti_overlay(scalars, "cortex_right", 1, "x").values,
      fully = detail::cifti_overlay(scalars, "CIFTI_STRUCTURE_CORTEX_RIGHT", 1, "x").values;
  ASSERT_EQ(shortly.size(), fully.size());
  for (size_t v = 0; v < fully.size(); ++v)
    EXPECT_TRUE(std::isnan(fully[v]) ? std::isnan(shortly[v]) : shortly[v] == fully[v]) << v;
  const detail::CiftiFile series = detail::read_cifti(file("lr.dtseries.nii"));
  EXPECT_EQ(series.kind, detail::CiftiMapKind::series);
  EXPECT_EQ(series.maps, 5);
  test::expect_error([&] { detail::cifti_overlay(series, "CORTEX_LEFT", 5, "x"); },
                     {"frame 5 asked for", "5 frames"});
}

TEST_F(Cifti, LabelMapsCarryTheirOwnTables) {
  const CiftiReference ref = read_cifti_reference(file("lr.dlabel.nii"));
  const detail::CiftiFile c = detail::read_cifti(file("lr.dlabel.nii"));
  EXPECT_EQ(c.kind, detail::CiftiMapKind::labels);
  ASSERT_EQ(ref.labels.size(), 2u);
  for (int map = 0; map < 2; ++map) {
    const detail::VertexOverlay o = detail::cifti_overlay(c, "CORTEX_LEFT", map, "x");
    EXPECT_TRUE(o.labels);
    const std::vector<detail::OverlayLabel>& want = ref.labels[static_cast<size_t>(map)];
    ASSERT_EQ(o.table.size(), want.size()) << map;
    for (size_t k = 0; k < want.size(); ++k) {
      EXPECT_EQ(o.table[k].key, want[k].key);
      EXPECT_EQ(o.table[k].name, want[k].name);
      EXPECT_EQ(o.table[k].rgba, want[k].rgba) << o.table[k].name;
    }
  }
}

TEST_F(Cifti, TheSurfaceSaysWhichStructureItIs) {
  const detail::CiftiFile c = detail::read_cifti(file("lr.dscalar.nii"));
  // Metadata first (the name says nothing), then the name, then the only structure of its count.
  EXPECT_EQ(detail::cifti_structure_of_surface(c, file("cortex.surf.gii"), 10),
            "CIFTI_STRUCTURE_CORTEX_RIGHT");
  EXPECT_EQ(detail::cifti_structure_of_surface(c, file("sub.L.white.surf.gii"), 10),
            "CIFTI_STRUCTURE_CORTEX_LEFT");
  EXPECT_EQ(detail::cifti_structure_of_surface(c, "/x/rh.pial", 10),
            "CIFTI_STRUCTURE_CORTEX_RIGHT");
  const detail::CiftiFile counts = detail::read_cifti(file("counts.dscalar.nii"));
  EXPECT_EQ(detail::cifti_structure_of_surface(counts, file("twelve.surf.gii"), 12),
            "CIFTI_STRUCTURE_CORTEX_RIGHT");
  // Both hemispheres have 10 vertices and the surface names neither.
  test::expect_error(
      [&] { detail::cifti_structure_of_surface(c, file("plain.surf.gii"), 10); },
      {"which of its structures the surface plain.surf.gii (10 vertices) shows is not known",
       "several", "give the overlay's \"structure\""});
  test::expect_error(
      [&] { detail::cifti_structure_of_surface(counts, file("plain.surf.gii"), 11); },
      {"none of the file's have 11 vertices"});
  // A surface that says what it is must be in the file.
  const detail::CiftiFile series = detail::read_cifti(file("lr.dtseries.nii"));
  EXPECT_EQ(detail::cifti_structure_of_surface(series, file("cortex.surf.gii"), 10),
            "CIFTI_STRUCTURE_CORTEX_RIGHT");
  // A name that says both sides says neither.
  test::expect_error([&] { detail::cifti_structure_of_surface(c, "/x/lh.pial.R", 10); },
                     {"not known"});
}

TEST_F(Cifti, OverlayFilesAndVolumesSayWhatACiftiFileIs) {
  EXPECT_TRUE(detail::is_cifti(file("lr.dlabel.nii")));
  EXPECT_FALSE(detail::is_cifti(file("plain.nii")));
  EXPECT_FALSE(detail::is_cifti(file("cortex.surf.gii")));
  EXPECT_TRUE(detail::is_overlay_file(file("lr.dtseries.nii")));
  // Alone, a file of two structures cannot choose; the one-structure choice is the registry's.
  test::expect_error([&] { detail::read_vertex_overlay(file("lr.dscalar.nii")); },
                     {"CORTEX_LEFT (10 vertices), CORTEX_RIGHT (10 vertices)", "\"structure\""});
  test::expect_error([&] { read_volume(file("lr.dtseries.nii")); },
                     {"lr.dtseries.nii is a CIFTI-2 file of surface data",
                      "intermix render fs_LR.32k.L.inflated.surf.gii lr.dtseries.nii"});
  test::expect_error([&] { detail::read_cifti(file("lr.pscalar.nii")); },
                     {"parcellated", "CIFTI_INDEX_TYPE_PARCELS"});
  test::expect_error([&] { detail::read_cifti(file("plain.nii")); },
                     {"not a CIFTI file", "intent code 0"});
}

// A copy of `name` with `from` (in the XML) replaced by `to`, of the same length.
std::filesystem::path patched(const test::TempDir& dir, const std::filesystem::path& source,
                              const std::string& from, const std::string& to) {
  std::string bytes = read_bytes(source);
  const size_t at = bytes.find(from);
  EXPECT_NE(at, std::string::npos) << from;
  EXPECT_EQ(from.size(), to.size());
  if (at != std::string::npos) bytes.replace(at, from.size(), to);
  const std::filesystem::path out = dir / source.filename();
  write_bytes(out, bytes);
  return out;
}

TEST_F(Cifti, CountsThatLieAreRefusedNamingTheField) {
  test::TempDir dir;
  const std::filesystem::path scalars = file("lr.dscalar.nii");
  // Vertex 5 of the left cortex past a surface of 5 vertices.
  test::expect_error(
      [&] {
        detail::read_cifti(patched(dir, scalars, "SurfaceNumberOfVertices=\"10\"",
                                   "SurfaceNumberOfVertices=\"05\""));
      },
      {"brain model CORTEX_LEFT lists vertex 5", "SurfaceNumberOfVertices 5"});
  test::expect_error(
      [&] { detail::read_cifti(patched(dir, scalars, "0 2 3 5 7 8", "0 2 3 5 7 2")); },
      {"CORTEX_LEFT lists vertex 2 twice"});
  test::expect_error(
      [&] { detail::read_cifti(patched(dir, scalars, "IndexCount=\"6\"", "IndexCount=\"5\"")); },
      {"brain model CORTEX_LEFT has IndexCount 5 but 6 VertexIndices"});
  test::expect_error(
      [&] { detail::read_cifti(patched(dir, scalars, "IndexOffset=\"6\"", "IndexOffset=\"7\"")); },
      {"CORTEX_RIGHT has IndexOffset 7", "end at 6"});
  test::expect_error(
      [&] { detail::read_cifti(patched(dir, scalars, "0 2 3 5 7 8", "0 2 x 5 7 8")); },
      {"<VertexIndices> of CIFTI_STRUCTURE_CORTEX_LEFT holds 'x'"});
  // dim[6] (brainordinates) of 14 where the brain models give 13.
  std::string bytes = read_bytes(scalars);
  int64_t dim6 = 0;
  std::memcpy(&dim6, bytes.data() + 16 + 6 * 8, 8);
  ASSERT_EQ(dim6, 13);
  dim6 = 14;
  std::memcpy(bytes.data() + 16 + 6 * 8, &dim6, 8);
  write_bytes(dir / "dims.dscalar.nii", bytes);
  test::expect_error([&] { detail::read_cifti(dir / "dims.dscalar.nii"); },
                     {"the data is 2 x 14 (dim[5] x dim[6])", "2 maps x 13 brainordinates"});
  // Data cut short.
  write_bytes(dir / "short.dscalar.nii", read_bytes(scalars).substr(0, bytes.size() - 4));
  test::expect_error([&] { detail::read_cifti(dir / "short.dscalar.nii"); },
                     {"expected 104 bytes of data"});
  // XML that is not well-formed.
  test::expect_error(
      [&] { detail::read_cifti(patched(dir, scalars, "<CIFTI Version", "<!DOCTYPE a [<")); },
      {"the CIFTI-2 XML"});
}

}  // namespace
}  // namespace imx
