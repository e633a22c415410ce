// Surfice MZ3 meshes and overlays (io/mesh/mz3.hpp): the real files of the shared data and
// fixtures, each checked against an independent parse of the same bytes in Python
// (/usr/bin/python3: gzip, struct, numpy), and damaged files, each refused with a clear error.
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <functional>
#include <sstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "core/colour.hpp"
#include "expect_error.hpp"
#include "intermix/error.hpp"
#include "io/mesh/mz3.hpp"
#include "io/streams/gzip.hpp"
#include "shared_data.hpp"
#include "temp_dir.hpp"

namespace imx {
namespace {

using test::read_bytes;

// Writes the fixtures (write()) and, for each file named on the command line or written, what
// an independent reading of its bytes finds (parse(): NAME.ref, all little-endian float64:
// attr, faces, vertices, layers, then the faces, the vertices, the RGBA bytes and the scalars).
const char* const kMz3Script = R"PY(
import gzip, os, struct, sys
import numpy as np

def parse(path, out):
    b = open(path, 'rb').read()
    if b[:2] == b'\x1f\x8b':
        b = gzip.decompress(b)
    magic, attr, nface, nvert, nskip = struct.unpack_from('<HHIII', b, 0)
    assert magic == 23117
    pos = 16 + nskip
    nf = nface if attr & 1 else 0
    faces = np.frombuffer(b, '<i4', 3 * nf, pos); pos += 12 * nf
    nv = nvert if attr & 2 else 0
    verts = np.frombuffer(b, '<f4', 3 * nv, pos); pos += 12 * nv
    nc = nvert if attr & 4 else 0
    rgba = np.frombuffer(b, 'u1', 4 * nc, pos); pos += 4 * nc
    size = 8 if attr & 16 else 4
    layers = (len(b) - pos) // (nvert * size) if attr & 24 else 0
    scalars = np.frombuffer(b, '<f8' if size == 8 else '<f4', layers * nvert, pos)
    parts = [np.array([attr, nf, nvert, layers]), faces, verts, rgba, scalars]
    np.concatenate([p.astype('<f8') for p in parts]).tofile(out)

def write(name, attr, faces=None, verts=None, rgba=None, scalars=None, skip=b'', gz=False):
    nvert = len(verts) if verts is not None else (len(rgba) if rgba is not None else scalars.shape[1])
    nface = len(faces) if faces is not None else 0
    b = struct.pack('<HHIII', 23117, attr, nface, nvert, len(skip)) + skip
    for part in (faces, verts, rgba, scalars):
        if part is not None:
            b += part.tobytes()
    open(name, 'wb').write(gzip.compress(b) if gz else b)
    parse(name, name + '.ref')

rng = np.random.default_rng(3)
n, f = 60, 100
verts = rng.uniform(-90, 90, (n, 3)).astype('<f4')
faces = np.array([rng.choice(n, 3, replace=False) for _ in range(f)], '<i4')
rgba = rng.integers(0, 256, (n, 4)).astype('u1')
layers = rng.normal(0, 3, (3, n)).astype('<f4')
layers[1, 7] = np.nan
write('mesh.mz3', 3, faces, verts)
write('mesh_gz.mz3', 3, faces, verts, gz=True)
write('coloured.mz3', 1 | 2 | 4 | 8, faces, verts, rgba, layers, gz=True)
write('coloured_raw.mz3', 1 | 2 | 4 | 8, faces, verts, rgba, layers)
write('private.mz3', 3 | 8, faces, verts, scalars=layers[:1], skip=b'private data 23 bytes.\n')
write('ao.mz3', 3 | 8 | 32, faces, verts, scalars=layers[:2], gz=True)
write('values.mz3', 8, scalars=layers, gz=True)
write('doubles.mz3', 16, scalars=rng.normal(0, 1e6, (2, n)).astype('<f8'))
write('doubles_gz.mz3', 16, scalars=rng.normal(0, 1, (1, n)).astype('<f8'), gz=True)
regions = rng.integers(1, 5, n)
palette = rng.integers(0, 256, (5, 4)).astype('u1')
tmpl = regions.astype('<f4')[None, :].copy()
tmpl[0, 3] = np.nan
write('template.mz3', 4 | 8, rgba=palette[regions], scalars=tmpl)
write('colours_only.mz3', 4, rgba=rgba)
for path in sys.argv[1:]:
    parse(path, os.path.basename(path) + '.ref')
)PY";

// The real files of the shared data (the Surfice and NiiVue samples).
const char* const kRealFiles[] = {"neuro/surfaces/BrainMesh_ICBM152.lh.mz3",
                                  "neuro/surfaces/BrainMesh_ICBM152.lh.motor.mz3",
                                  "neuro/surfaces/xd.mz3",
                                  "neuro/surfaces/mz3/3Mesh.mz3",
                                  "neuro/surfaces/mz3/11ScalarMesh.mz3",
                                  "neuro/surfaces/mz3/cortex_5124.mz3",
                                  "neuro/surfaces/mz3/16DoubleOverlay_5124x2.mz3"};

bool have_numpy() {
  static const bool ok =
      std::system("/usr/bin/python3 -c 'import numpy, gzip, struct' >/dev/null 2>&1") == 0;
  return ok;
}

// What the Python parse found.
struct Reference {
  int attr = 0;
  size_t faces = 0, vertices = 0, layers = 0;
  std::vector<double> face_indices, positions, rgba, scalars;
};

Reference read_reference(const std::filesystem::path& file) {
  const std::string bytes = read_bytes(file);
  std::vector<double> d(bytes.size() / 8);
  std::memcpy(d.data(), bytes.data(), d.size() * 8);
  Reference r;
  if (d.size() < 4) {
    ADD_FAILURE() << "no reference " << file;
    return r;
  }
  r.attr = static_cast<int>(d[0]);
  r.faces = static_cast<size_t>(d[1]);
  r.vertices = static_cast<size_t>(d[2]);
  r.layers = static_cast<size_t>(d[3]);
  auto at = d.begin() + 4;
  auto take = [&](size_t n) {
    std::vector<double> part(at, at + static_cast<std::ptrdiff_t>(n));
    at += static_cast<std::ptrdiff_t>(n);
    return part;
  };
  const size_t nv = (r.attr & 2) ? r.vertices : 0, nc = (r.attr & 4) ? r.vertices : 0;
  EXPECT_EQ(d.size(), 4 + 3 * r.faces + 3 * nv + 4 * nc + r.layers * r.vertices) << file;
  r.face_indices = take(3 * r.faces);
  r.positions = take(3 * nv);
  r.rgba = take(4 * nc);
  r.scalars = take(r.layers * r.vertices);
  return r;
}

// Equal, NaN equal to NaN.
void expect_same_values(const std::vector<double>& got, const double* want, size_t n,
                        const std::string& what) {
  ASSERT_EQ(got.size(), n) << what;
  int wrong = 0;
  for (size_t i = 0; i < n; ++i) {
    const bool same = std::isnan(want[i]) ? std::isnan(got[i]) : got[i] == want[i];
    if (!same && wrong++ < 5)
      ADD_FAILURE() << what << " value " << i << ": " << got[i] << " vs " << want[i];
  }
  EXPECT_EQ(wrong, 0) << what;
}

// A mesh as read against the reference: every face, vertex, colour and scalar layer.
void expect_mesh_matches(const detail::PolyDataFile& m, const Reference& r,
                         const std::string& what) {
  ASSERT_EQ(m.mesh.positions.size(), r.vertices) << what;
  ASSERT_EQ(m.mesh.triangles.size(), r.faces) << what;
  ASSERT_TRUE(m.space.has_value());
  EXPECT_EQ(*m.space, MeshSpace::ras) << what;
  for (size_t v = 0; v < r.vertices; ++v)
    for (int c = 0; c < 3; ++c)
      ASSERT_EQ(m.mesh.positions[v][c], r.positions[3 * v + static_cast<size_t>(c)])
          << what << " vertex " << v;
  for (size_t t = 0; t < r.faces; ++t)
    for (int c = 0; c < 3; ++c)
      ASSERT_EQ(m.mesh.triangles[t][c], r.face_indices[3 * t + static_cast<size_t>(c)])
          << what << " face " << t;
  if (r.rgba.empty()) {
    EXPECT_TRUE(m.mesh.colors.empty()) << what;
  } else {
    ASSERT_EQ(m.mesh.colors.size(), r.vertices) << what;
    for (size_t v = 0; v < r.vertices; ++v)
      for (int c = 0; c < 3; ++c)
        ASSERT_FLOAT_EQ(
            m.mesh.colors[v][c],
            srgb_decode(static_cast<float>(r.rgba[4 * v + static_cast<size_t>(c)]) / 255.0f))
            << what << " colour " << v;
  }
  ASSERT_EQ(m.point_data.size(), r.layers) << what;
  for (size_t l = 0; l < r.layers; ++l) {
    EXPECT_EQ(m.point_data[l].components, 1);
    expect_same_values(m.point_data[l].values, r.scalars.data() + l * r.vertices, r.vertices,
                       what + " layer " + std::to_string(l));
  }
}

class Mz3Files : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    if (!have_numpy()) return;
    dir_ = new test::TempDir;
    std::string command = "cd '" + dir_->path().string() + "' && /usr/bin/python3 make.py";
    for (const char* name : kRealFiles)
      if (std::filesystem::exists(test::shared_data(name)))
        command += " '" + test::shared_data(name).string() + "'";
    test::write_bytes(*dir_ / "make.py", kMz3Script);
    ok_ = std::system((command + " >make.log 2>&1").c_str()) == 0;
  }
  static void TearDownTestSuite() {
    delete dir_;
    dir_ = nullptr;
  }
  void SetUp() override {
    if (!have_numpy()) GTEST_SKIP() << "/usr/bin/python3 with numpy is not available";
    ASSERT_TRUE(ok_) << "the Python script failed:\n" << read_bytes(*dir_ / "make.log");
  }
  static std::filesystem::path file(const std::string& name) { return *dir_ / name; }
  static Reference reference(const std::filesystem::path& file) {
    return read_reference(*dir_ / (file.filename().string() + ".ref"));
  }
  // `name`'s bytes (uncompressed), changed by `edit`, written raw as `out` and gzipped as
  // out + ".gz.mz3".
  template <class Edit>
  static std::filesystem::path edited(const std::string& name, const std::string& out, Edit edit) {
    std::string bytes = read_bytes(file(name));
    edit(bytes);
    test::write_bytes(file(out), bytes);
    std::ostringstream gz;
    detail::gzip({reinterpret_cast<const uint8_t*>(bytes.data()), bytes.size()}, gz, 6, out);
    test::write_bytes(file(out + ".gz.mz3"), gz.str());
    return file(out);
  }

 private:
  inline static test::TempDir* dir_ = nullptr;
  inline static bool ok_ = false;
};

void put_u32(std::string& bytes, size_t at, uint32_t v) {
  std::memcpy(bytes.data() + at, &v, 4);
}
void put_u16(std::string& bytes, size_t at, uint16_t v) {
  std::memcpy(bytes.data() + at, &v, 2);
}

TEST_F(Mz3Files, RealFilesReadAsThePythonParseDoes) {
  SKIP_WITHOUT_SHARED_DATA("neuro/surfaces/mz3");
  int meshes = 0, overlays = 0;
  for (const char* name : kRealFiles) {
    const std::filesystem::path path = test::shared_data(name);
    if (!std::filesystem::exists(path)) continue;
    const Reference r = reference(path);
    SCOPED_TRACE(name);
    EXPECT_EQ(detail::mz3_is_overlay(path), (r.attr & 1) == 0);
    if (r.attr & 1) {
      ++meshes;
      expect_mesh_matches(detail::read_mz3_mesh(path), r, name);
      ASSERT_GT(r.vertices, 0u);
    } else {
      ++overlays;
      ASSERT_GE(r.layers, 1u);
      for (size_t l = 0; l < r.layers; ++l) {
        const detail::VertexOverlay o = detail::read_mz3_overlay(path, static_cast<int>(l));
        EXPECT_EQ(o.claimed_vertices, r.vertices);
        EXPECT_FALSE(o.labels);
        expect_same_values(o.values, r.scalars.data() + l * r.vertices, r.vertices,
                           std::string(name) + " layer " + std::to_string(l));
      }
      EXPECT_EQ(detail::read_mz3_overlay(path, -1).values,
                detail::read_mz3_overlay(path, 0).values);
      test::expect_error([&] { detail::read_mz3_mesh(path); }, {name, "overlay"});
    }
  }
  // BrainMesh and its motor map, xd, 3Mesh, 11ScalarMesh, cortex_5124, the double overlay.
  EXPECT_EQ(meshes + overlays, 7);
  EXPECT_EQ(overlays, 3);
}

// The mesh and its overlay belong together: as many values as the surface has vertices.
TEST_F(Mz3Files, MotorMapFitsItsSurface) {
  SKIP_WITHOUT_SHARED_DATA("neuro/surfaces/BrainMesh_ICBM152.lh.mz3",
                           "neuro/surfaces/BrainMesh_ICBM152.lh.motor.mz3");
  const auto mesh =
      detail::read_mz3_mesh(test::shared_data("neuro/surfaces/BrainMesh_ICBM152.lh.mz3"));
  const auto motor = detail::read_mz3_overlay(
      test::shared_data("neuro/surfaces/BrainMesh_ICBM152.lh.motor.mz3"), -1);
  EXPECT_EQ(detail::overlay_values(motor, mesh.mesh.positions.size(), "motor").size(),
            mesh.mesh.positions.size());
}

TEST_F(Mz3Files, RawAndGzipMeshesMatchTheParse) {
  for (const char* name :
       {"mesh.mz3", "mesh_gz.mz3", "coloured.mz3", "coloured_raw.mz3", "private.mz3", "ao.mz3"}) {
    const Reference r = reference(file(name));
    expect_mesh_matches(detail::read_mz3_mesh(file(name)), r, name);
    EXPECT_FALSE(detail::mz3_is_overlay(file(name))) << name;
  }
  const detail::PolyDataFile c = detail::read_mz3_mesh(file("coloured.mz3"));
  ASSERT_EQ(c.point_data.size(), 3u);
  EXPECT_EQ(c.point_data[0].name, "scalars");
  EXPECT_EQ(c.point_data[1].name, "scalars1");
  EXPECT_EQ(c.point_data[2].name, "scalars2");
  EXPECT_TRUE(std::isnan(c.point_data[1].values[7]));
  const detail::PolyDataFile ao = detail::read_mz3_mesh(file("ao.mz3"));
  ASSERT_EQ(ao.point_data.size(), 2u);
  EXPECT_EQ(ao.point_data[0].name, "ambient_occlusion");
  EXPECT_EQ(ao.point_data[1].name, "scalars");
}

TEST_F(Mz3Files, OverlaysOfFloatAndDoubleLayers) {
  for (const char* name : {"values.mz3", "doubles.mz3", "doubles_gz.mz3"}) {
    const Reference r = reference(file(name));
    EXPECT_TRUE(detail::mz3_is_overlay(file(name))) << name;
    ASSERT_GE(r.layers, 1u) << name;
    for (size_t l = 0; l < r.layers; ++l)
      expect_same_values(detail::read_mz3_overlay(file(name), static_cast<int>(l)).values,
                         r.scalars.data() + l * r.vertices, r.vertices,
                         std::string(name) + " layer " + std::to_string(l));
    test::expect_error([&] { detail::read_mz3_overlay(file(name), static_cast<int>(r.layers)); },
                       {name, "no layer " + std::to_string(r.layers)});
  }
  // A mesh's scalars read as an overlay too (as NiiVue's layers do); the AO map is passed over.
  const Reference ao = reference(file("ao.mz3"));
  expect_same_values(detail::read_mz3_overlay(file("ao.mz3"), -1).values,
                     ao.scalars.data() + ao.vertices, ao.vertices, "ao.mz3 first value layer");
  test::expect_error([&] { detail::read_mz3_overlay(file("values.mz3"), -2); }, {"layer -2"});
}

// Colours and scalars together are a template: integer regions, one colour each.
TEST_F(Mz3Files, TemplateBecomesALabelOverlay) {
  const Reference r = reference(file("template.mz3"));
  const detail::VertexOverlay o = detail::read_mz3_overlay(file("template.mz3"), -1);
  ASSERT_TRUE(o.labels);
  expect_same_values(o.values, r.scalars.data(), r.vertices, "template");
  for (size_t v = 0; v < r.vertices; ++v) {
    if (std::isnan(r.scalars[v])) continue;
    const auto key = static_cast<int64_t>(r.scalars[v]);
    const detail::OverlayLabel* label = nullptr;
    for (const auto& l : o.table)
      if (l.key == key) label = &l;
    ASSERT_NE(label, nullptr) << "region " << key;
    for (int c = 0; c < 4; ++c)
      EXPECT_FLOAT_EQ(label->rgba[c],
                      static_cast<float>(r.rgba[4 * v + static_cast<size_t>(c)]) / 255.0f);
  }
  // A region of two colours, a region number that is no integer.
  edited("template.mz3", "two_colours.mz3", [&](std::string& b) {
    const size_t rgba = 16;
    for (size_t v = 1; v < r.vertices; ++v)
      if (r.scalars[v] == r.scalars[0]) {
        b[rgba + 4 * v] = static_cast<char>(static_cast<uint8_t>(b[rgba]) ^ 0x40);
        break;
      }
  });
  test::expect_error([&] { detail::read_mz3_overlay(file("two_colours.mz3"), -1); },
                     {"two_colours.mz3", "two colours"});
  edited("template.mz3", "fraction.mz3", [&](std::string& b) {
    const float x = 2.5f;
    std::memcpy(b.data() + 16 + 4 * r.vertices + 4 * 5, &x, 4);
  });
  test::expect_error([&] { detail::read_mz3_overlay(file("fraction.mz3"), -1); },
                     {"fraction.mz3", "vertex 5", "2.5", "not an integer"});
  test::expect_error([&] { detail::read_mz3_overlay(file("colours_only.mz3"), -1); },
                     {"colours_only.mz3", "no scalars", "only colours"});
  test::expect_error([&] { detail::read_mz3_mesh(file("colours_only.mz3")); }, {"overlay"});
}

// Files whose header lies or whose data is damaged, raw and gzipped: one clear error each.
TEST_F(Mz3Files, DamagedFilesAreRefused) {
  const Reference r = reference(file("mesh.mz3"));
  const size_t faces_at = 16, verts_at = 16 + 12 * r.faces;
  struct Case {
    const char* name;
    std::function<void(std::string&)> edit;
    std::vector<std::string> fragments;
  };
  const std::vector<Case> cases = {
      {"too_many_faces.mz3",
       [](std::string& b) { put_u32(b, 4, 0x7fffffffu); },
       {"2147483647 faces"}},
      {"too_many_vertices.mz3",
       [](std::string& b) { put_u32(b, 8, 0xffffffffu); },
       {"4294967295 vertices"}},
      {"face_out_of_range.mz3",
       [&](std::string& b) {
         put_u32(b, faces_at + 12 * 9 + 4, static_cast<uint32_t>(r.vertices));
       },
       {"face 9 uses vertex 60, but the file has 60 vertices"}},
      {"negative_face.mz3",
       [&](std::string& b) { put_u32(b, faces_at, 0xffffffffu); },
       {"face 0 uses vertex -1"}},
      {"nan_vertex.mz3",
       [&](std::string& b) {
         const float nan = std::nanf("");
         std::memcpy(b.data() + verts_at + 12 * 4 + 8, &nan, 4);
       },
       {"vertex 4", "non-finite"}},
      {"truncated.mz3", [](std::string& b) { b.resize(b.size() - 5); }, {"truncated"}},
      {"surplus.mz3", [](std::string& b) { b += "xyz"; }, {"3 bytes follow"}},
      {"future.mz3", [](std::string& b) { put_u16(b, 2, 64 | 3); }, {"ATTR 67", "future version"}},
      {"faces_only.mz3", [](std::string& b) { put_u16(b, 2, 1); }, {"isFACE and isVERT differ"}},
      {"float_and_double.mz3",
       [](std::string& b) { put_u16(b, 2, 3 | 8 | 16); },
       {"isSCALAR and isDOUBLE"}},
      {"no_faces_count.mz3", [](std::string& b) { put_u32(b, 4, 0); }, {"NFACE is 0"}},
      {"two_vertices.mz3", [](std::string& b) { put_u32(b, 8, 2); }, {"NVERT is 2"}},
      {"bad_magic.mz3", [](std::string& b) { b[0] = 'X'; }, {"not an MZ3 file"}},
      {"skip_past_end.mz3", [](std::string& b) { put_u32(b, 12, 1u << 30); }, {"NSKIP"}},
      {"header_only.mz3", [](std::string& b) { b.resize(10); }, {"shorter than the 16-byte"}},
      {"partial_layer.mz3",
       [](std::string& b) {
         put_u16(b, 2, 3 | 8);
         b += std::string(4 * 59, '\0');
       },
       {"236 bytes of scalars are not whole layers of 60 float32"}},
      {"no_layer.mz3", [](std::string& b) { put_u16(b, 2, 3 | 8); }, {"0 bytes of scalars"}},
  };
  for (const Case& c : cases) {
    const std::filesystem::path raw = edited("mesh.mz3", c.name, c.edit);
    std::filesystem::path gz = raw;
    gz += ".gz.mz3";
    for (const auto& path : {raw, gz}) {
      SCOPED_TRACE(path.filename().string());
      const std::string message = test::error_of([&] { detail::read_mz3_mesh(path); });
      EXPECT_NE(message.find(path.string()), std::string::npos) << message;
      for (const std::string& f : c.fragments)
        EXPECT_NE(message.find(f), std::string::npos) << "'" << f << "' missing: " << message;
    }
  }
  // Gzip data cut short, or damaged: zlib's checks, named as such.
  std::string gz = read_bytes(file("mesh_gz.mz3"));
  test::write_bytes(file("cut.mz3"), gz.substr(0, gz.size() / 2));
  test::expect_error([&] { detail::read_mz3_mesh(file("cut.mz3")); }, {"cut.mz3", "truncated"});
  gz[gz.size() - 6] ^= 0x55;  // the CRC
  test::write_bytes(file("crc.mz3"), gz);
  test::expect_error([&] { detail::read_mz3_mesh(file("crc.mz3")); }, {"crc.mz3"});
  test::expect_error([&] { detail::mz3_is_overlay(file("nowhere.mz3")); }, {"nowhere.mz3"});
}

// A gzip file claiming more than its compressed bytes can inflate to is refused before any
// allocation; an overlay's scalar layers are bounded by the memory budget as they inflate.
TEST_F(Mz3Files, GzipClaimsAreBoundedBeforeInflating) {
  std::string header(16, '\0');
  put_u16(header, 0, 23117);
  put_u16(header, 2, 3);
  put_u32(header, 4, 1000000000u);
  put_u32(header, 8, 1000000000u);
  std::ostringstream gz;
  detail::gzip({reinterpret_cast<const uint8_t*>(header.data()), header.size()}, gz, 6, "h");
  test::write_bytes(file("huge_claim.mz3"), gz.str());
  test::expect_error([&] { detail::read_mz3_mesh(file("huge_claim.mz3")); },
                     {"huge_claim.mz3", "1000000000 faces", "can inflate to"});
}

}  // namespace
}  // namespace imx
