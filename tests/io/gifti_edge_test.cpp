// GIfTI files as nibabel 5.0 reads them, at the edges of the format: labels numbered by Index
// (older files), files of values alone, the legacy encoding names (B64BIN, GIFTI_ENCODING_*),
// and ColumnMajorOrder in binary and ASCII data. Each fixture is written by nibabel (its XML
// text edited where nibabel no longer writes the old form) and compared with nibabel's reading.
#include <cmath>
#include <cstring>
#include <filesystem>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "expect_error.hpp"
#include "intermix/error.hpp"
#include "intermix/io.hpp"
#include "io/mesh/gifti_reader.hpp"
#include "io/overlay/vertex_overlay.hpp"
#include "nibabel_reference.hpp"
#include "shared_data.hpp"
#include "temp_dir.hpp"

namespace imx {
namespace {

using test::read_bytes;

// gref(path) writes path.ref (the POINTSET then the TRIANGLE array, else every array, as
// float64, row by row as nibabel shapes them), path.shape (each array's shape, "40x3 70x3") and,
// for a label table, path.labels (key, red, green, blue, alpha each) and path.names.
const char* const kGiftiScript = R"PY(
import re
def gref(path, out=None):
    out = out or os.path.basename(path)
    g = nib.load(path)
    p = g.get_arrays_from_intent('NIFTI_INTENT_POINTSET')
    t = g.get_arrays_from_intent('NIFTI_INTENT_TRIANGLE')
    arrays = [p[0], t[0]] if p and t else list(g.darrays)
    with open(out + '.shape', 'w') as fo:
        fo.write(' '.join('x'.join(map(str, a.data.shape)) for a in arrays))
    np.concatenate([np.asarray(a.data, '<f8').ravel() for a in arrays]).tofile(out + '.ref')
    labels = g.labeltable.labels
    if labels:
        np.array([[l.key, l.red, l.green, l.blue, l.alpha] for l in labels], '<f8').tofile(out + '.labels')
        with open(out + '.names', 'w') as fo:
            fo.write('\n'.join(l.label for l in labels))

def save(name, text):
    with open(name, 'w') as fo:
        fo.write(text)
    gref(name)

def edit(text, old, new):
    assert old in text, old
    return text.replace(old, new)

rng = np.random.default_rng(21)
n, f = 40, 70
coords = rng.uniform(-80, 80, (n, 3)).astype(np.float32)
faces = np.array([rng.choice(n, 3, replace=False) for _ in range(f)], dtype=np.int32)

def surface(encoding, ordering='RowMajorOrder'):
    arrays = [nib.gifti.GiftiDataArray(coords, intent='NIFTI_INTENT_POINTSET',
                                       datatype='NIFTI_TYPE_FLOAT32', encoding=encoding,
                                       ordering=ordering),
              nib.gifti.GiftiDataArray(faces, intent='NIFTI_INTENT_TRIANGLE',
                                       datatype='NIFTI_TYPE_INT32', encoding=encoding,
                                       ordering=ordering)]
    return nib.gifti.GiftiImage(darrays=arrays).to_xml().decode()

# Legacy encoding names nibabel reads: B64BIN, and the GIFTI_ENCODING_ / GIFTI_ENDIAN_ constants.
save('b64bin.gii', edit(surface('B64BIN'), 'Encoding="Base64Binary"', 'Encoding="B64BIN"'))
save('constants.gii', edit(edit(surface('B64GZ'), 'Encoding="GZipBase64Binary"',
                                'Encoding="GIFTI_ENCODING_B64GZ"'),
                           'Endian="LittleEndian"', 'Endian="GIFTI_ENDIAN_LITTLE"'))
shape = nib.gifti.GiftiImage(darrays=[nib.gifti.GiftiDataArray(
    rng.normal(2, 1, n).astype(np.float64), intent='NIFTI_INTENT_SHAPE',
    datatype='NIFTI_TYPE_FLOAT64', encoding='B64BIN')]).to_xml().decode()
save('b64bin.shape.gii', edit(shape, 'Encoding="Base64Binary"', 'Encoding="B64BIN"'))

# ColumnMajorOrder: binary data in column order; ASCII as nibabel writes it (a row a line), a
# column a line as libgiftiio writes it (nibabel's arrays then take the wrong shape: 3 x n), and
# nibabel's writing of a surface of 3 vertices (3 lines of 3: rows or columns?).
save('binary_columns.gii', surface('B64GZ', 'ColumnMajorOrder'))
ascii = surface('ASCII', 'ColumnMajorOrder')
save('ascii_columns.gii', ascii)
blocks = iter(['\n'.join(' '.join('%.6f' % v for v in col) for col in coords.T),
               '\n'.join(' '.join('%d' % v for v in col) for col in faces.T)])
save('ascii_column_lines.gii',
     re.sub(r'<Data>(.*?)</Data>', lambda m: '<Data>' + next(blocks) + '</Data>', ascii, flags=re.S))
coords, faces = coords[:3], faces[:1] % 3
save('ascii_3x3.gii', surface('ASCII', 'ColumnMajorOrder'))

# Label tables numbered by Index (older GIfTI), and with both (nibabel takes Key).
table = nib.gifti.GiftiLabelTable()
for key, name, rgba in [(0, 'unknown', (0, 0, 0, 0)), (3, 'V1', (1, 0, 0, 1)),
                        (7, 'MT', (0.25, 0.5, 1, 0.75))]:
    l = nib.gifti.GiftiLabel(key=key, red=rgba[0], green=rgba[1], blue=rgba[2], alpha=rgba[3])
    l.label = name
    table.labels.append(l)
keys = rng.choice([0, 3, 7], n).astype(np.int32)
labels = nib.gifti.GiftiImage(labeltable=table, darrays=[nib.gifti.GiftiDataArray(
    keys, intent='NIFTI_INTENT_LABEL', datatype='NIFTI_TYPE_INT32')]).to_xml().decode()
save('index.label.gii', edit(labels, ' Key="', ' Index="'))
save('both.label.gii', edit(labels, ' Key="', ' Index="5" Key="'))

# Values alone: arrays of intent NONE, SHAPE and a statistic, no POINTSET.
values = nib.gifti.GiftiImage(darrays=[
    nib.gifti.GiftiDataArray(rng.normal(0, 1, n).astype(np.float32), intent='NIFTI_INTENT_NONE',
                             datatype='NIFTI_TYPE_FLOAT32'),
    nib.gifti.GiftiDataArray(rng.uniform(1, 4, n).astype(np.float32), intent='NIFTI_INTENT_SHAPE',
                             datatype='NIFTI_TYPE_FLOAT32', encoding='B64GZ'),
    nib.gifti.GiftiDataArray(rng.normal(0, 3, n).astype(np.float64), intent='NIFTI_INTENT_TTEST',
                             datatype='NIFTI_TYPE_FLOAT64', encoding='ASCII')])
save('values.func.gii', values.to_xml().decode())

sample = sys.argv[1] if len(sys.argv) > 1 else ''
if sample:
    gref(sample)
)PY";

std::vector<double> doubles(const std::filesystem::path& file) {
  const std::string bytes = read_bytes(file);
  std::vector<double> out(bytes.size() / 8);
  std::memcpy(out.data(), bytes.data(), out.size() * 8);
  return out;
}

class GiftiEdgeFiles : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    if (!test::have_nibabel()) return;
    dir_ = new test::TempDir;
    test::write_bytes(*dir_ / "make.py", std::string(test::kNibabelPrelude) + kGiftiScript);
    std::string command = "cd '" + dir_->path().string() + "' && /usr/bin/python3 make.py";
    if (std::filesystem::exists(test::shared_data("ColumnMajorOrder.gii")))
      command += " '" + test::shared_data("ColumnMajorOrder.gii").string() + "'";
    ok_ = std::system((command + " >make.log 2>&1").c_str()) == 0;
  }
  static void TearDownTestSuite() {
    delete dir_;
    dir_ = nullptr;
  }
  void SetUp() override {
    if (!test::have_nibabel()) GTEST_SKIP() << "/usr/bin/python3 with nibabel is not available";
    ASSERT_TRUE(ok_) << "the nibabel script failed:\n" << read_bytes(*dir_ / "make.log");
  }
  static std::filesystem::path file(const std::string& name) { return *dir_ / name; }

  // The surface intermix reads equals nibabel's POINTSET and TRIANGLE arrays, value for value.
  static void expect_surface_as_nibabel(const std::filesystem::path& path,
                                        const std::string& ref_name) {
    SCOPED_TRACE(path.filename().string());
    const Mesh mesh = detail::read_gifti(path);
    const std::vector<double> want = doubles(file(ref_name + ".ref"));
    const size_t n = mesh.positions.size();
    ASSERT_EQ(3 * (n + mesh.triangles.size()), want.size())
        << "nibabel's shapes: " << read_bytes(file(ref_name + ".shape"));
    for (size_t v = 0; v < n; ++v)
      for (int c = 0; c < 3; ++c)
        ASSERT_EQ(mesh.positions[v][c], want[3 * v + static_cast<size_t>(c)]) << "vertex " << v;
    for (size_t t = 0; t < mesh.triangles.size(); ++t)
      for (int c = 0; c < 3; ++c)
        ASSERT_EQ(mesh.triangles[t][c], want[3 * n + 3 * t + static_cast<size_t>(c)])
            << "triangle " << t;
  }

 private:
  inline static test::TempDir* dir_ = nullptr;
  inline static bool ok_ = false;
};

TEST_F(GiftiEdgeFiles, LegacyEncodingNamesReadAsNibabelReadsThem) {
  EXPECT_NE(read_bytes(file("b64bin.gii")).find("Encoding=\"B64BIN\""), std::string::npos);
  expect_surface_as_nibabel(file("b64bin.gii"), "b64bin.gii");
  EXPECT_NE(read_bytes(file("constants.gii")).find("GIFTI_ENCODING_B64GZ"), std::string::npos);
  expect_surface_as_nibabel(file("constants.gii"), "constants.gii");
  EXPECT_EQ(detail::read_vertex_overlay(file("b64bin.shape.gii")).values,
            doubles(file("b64bin.shape.gii.ref")));
  // External data stays refused, by any of its names.
  std::string text = read_bytes(file("b64bin.gii"));
  for (size_t at = 0; (at = text.find("Encoding=\"B64BIN\"", at)) != std::string::npos;)
    text.replace(at, 17, "Encoding=\"GIFTI_ENCODING_EXTBIN\"");
  test::write_bytes(file("external.gii"), text);
  test::expect_error([&] { detail::read_gifti(file("external.gii")); },
                     {"external.gii", "GIFTI_ENCODING_EXTBIN", "is not ASCII"});
}

TEST_F(GiftiEdgeFiles, ColumnMajorOrderReadsAsNibabel) {
  expect_surface_as_nibabel(file("binary_columns.gii"), "binary_columns.gii");
  // nibabel writes ASCII a row a line whatever the order, and reads it back so.
  expect_surface_as_nibabel(file("ascii_columns.gii"), "ascii_columns.gii");
  // A column a line (libgiftiio's writing): nibabel reads each line as a row, so its arrays
  // are 3 x n; intermix reads the surface they are the transpose of.
  ASSERT_EQ(read_bytes(file("ascii_column_lines.gii.shape")), "3x40 3x70");
  const Mesh columns = detail::read_gifti(file("ascii_column_lines.gii"));
  const std::vector<double> want = doubles(file("ascii_column_lines.gii.ref"));
  ASSERT_EQ(columns.positions.size(), 40u);
  ASSERT_EQ(columns.triangles.size(), 70u);
  for (size_t v = 0; v < 40; ++v)
    for (size_t c = 0; c < 3; ++c) ASSERT_EQ(columns.positions[v][c], want[c * 40 + v]);
  for (size_t t = 0; t < 70; ++t)
    for (size_t c = 0; c < 3; ++c) ASSERT_EQ(columns.triangles[t][c], want[120 + c * 70 + t]);
  // Three lines of three values: rows (nibabel) or columns (libgiftiio)? Refused.
  test::expect_error([&] { detail::read_gifti(file("ascii_3x3.gii")); },
                     {"ascii_3x3.gii", "data array 0", "ColumnMajorOrder", "3 lines of 3"});
}

TEST_F(GiftiEdgeFiles, ColumnMajorOrderSampleReadsAsNibabel) {
  SKIP_WITHOUT_SHARED_DATA("ColumnMajorOrder.gii");
  expect_surface_as_nibabel(test::shared_data("ColumnMajorOrder.gii"), "ColumnMajorOrder.gii");
}

TEST_F(GiftiEdgeFiles, LabelTablesByIndexOrKey) {
  for (const char* name : {"index.label.gii", "both.label.gii"}) {
    SCOPED_TRACE(name);
    const std::string text = read_bytes(file(name));
    EXPECT_NE(text.find(" Index=\""), std::string::npos);
    const detail::VertexOverlay o = detail::read_vertex_overlay(file(name));
    const std::vector<double> labels = doubles(file(std::string(name) + ".labels"));
    const std::string names = read_bytes(file(std::string(name) + ".names"));
    ASSERT_TRUE(o.labels);
    EXPECT_EQ(o.values, doubles(file(std::string(name) + ".ref")));
    ASSERT_EQ(o.table.size() * 5, labels.size());
    std::string joined;
    for (size_t k = 0; k < o.table.size(); ++k) {
      EXPECT_EQ(static_cast<double>(o.table[k].key), labels[5 * k]) << "label " << k;
      for (int c = 0; c < 4; ++c)
        EXPECT_FLOAT_EQ(o.table[k].rgba[c], static_cast<float>(labels[5 * k + 1 + c]));
      joined += (k ? "\n" : "") + o.table[k].name;
    }
    EXPECT_EQ(joined, names);
  }
  // A label with neither is refused (nibabel would give it key 0).
  std::string text = read_bytes(file("index.label.gii"));
  text.replace(text.find(" Index=\""), 7, " Other=");
  test::write_bytes(file("no_key.label.gii"), text);
  test::expect_error([&] { detail::read_vertex_overlay(file("no_key.label.gii")); },
                     {"no_key.label.gii", "no Key (or Index)"});
}

// Values alone: an overlay, each array as nibabel reads it; as a mesh, refused as an overlay.
TEST_F(GiftiEdgeFiles, DataOnlyFilesAreOverlaysThatNeedTheirSurface) {
  const std::vector<double> want = doubles(file("values.func.gii.ref"));
  ASSERT_EQ(want.size(), 3u * 40u);
  EXPECT_TRUE(detail::is_overlay_file(file("values.func.gii")));
  for (int a = 0; a < 3; ++a) {
    const detail::VertexOverlay o = detail::read_vertex_overlay(file("values.func.gii"), a);
    EXPECT_EQ(o.claimed_vertices, 40u);
    EXPECT_FALSE(o.labels);
    EXPECT_EQ(o.values, std::vector<double>(want.begin() + 40 * a, want.begin() + 40 * (a + 1)))
        << "array " << a;
  }
  EXPECT_EQ(detail::read_vertex_overlay(file("values.func.gii")).values,
            std::vector<double>(want.begin(), want.begin() + 40));
  for (const auto& read : {+[](const std::filesystem::path& p) { detail::read_gifti(p); },
                           +[](const std::filesystem::path& p) { read_mesh_file(p); }})
    test::expect_error(
        [&] { read(file("values.func.gii")); },
        {"values.func.gii", "no NIFTI_INTENT_POINTSET", "NIFTI_INTENT_NONE", "NIFTI_INTENT_SHAPE",
         "NIFTI_INTENT_TTEST", "overlay", "surface it belongs to"});
}

}  // namespace
}  // namespace imx
