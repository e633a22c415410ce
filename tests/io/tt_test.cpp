// DSI Studio TinyTrack (.tt.gz, io/streamlines/tt.hpp): the shared data's TR_S_R.tt.gz and
// fixtures, each checked against an independent decoding of the same bytes in Python
// (/usr/bin/python3: gzip, struct, numpy) that follows DSI Studio's documented layout and NiiVue's
// placement; damaged files, each refused with one clear error.
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <sstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "expect_error.hpp"
#include "intermix/error.hpp"
#include "intermix/limits.hpp"
#include "io/streamlines/tt.hpp"
#include "io/streams/gzip.hpp"
#include "shared_data.hpp"
#include "temp_dir.hpp"

namespace imx {
namespace {

using test::read_bytes;
using test::write_bytes;

// write(): the fixtures; parse(): for a file, NAME.ref, little-endian: int64 count, int64
// offsets (count + 1), float64 RAS points (x, y, z each), as the layout's documentation reads.
const char* const kTtScript = R"PY(
import gzip, os, struct, sys
import numpy as np

TYPES = ['f8', 'f4', 'i4', 'i2', 'u2', 'u1']

def matrices(b):
    out, pos = {}, 0
    while pos < len(b):
        t = struct.unpack_from('<i', b, pos)[0]
        end = '<' if 0 <= t < 1000 else '>'
        t, rows, cols, imag, namlen = struct.unpack_from(end + '5i', b, pos)
        name = b[pos + 20:pos + 20 + namlen].split(b'\0')[0].decode()
        pos += 20 + namlen
        a = np.frombuffer(b, end + TYPES[t // 10 % 10], rows * cols, pos)
        pos += a.nbytes * (2 if imag else 1)
        out[name] = a
    return out

def parse(path, out):
    b = open(path, 'rb').read()
    if b[:2] == b'\x1f\x8b':
        b = gzip.decompress(b)
    m = matrices(b)
    if 'trans_to_mni' in m:
        T = m['trans_to_mni'].astype(np.float64).reshape(4, 4)  # row by row
    else:
        d, v = m['dimension'].astype(np.float64), m['voxel_size'].astype(np.float64)
        T = np.array([[-v[0], 0, 0, v[0] * (d[0] - 1)], [0, -v[1], 0, v[1] * (d[1] - 1)],
                      [0, 0, v[2], 0], [0, 0, 0, 1]])
    track = m['track'].tobytes()
    offsets, points, p = [0], [], 0
    while p < len(track):
        size = struct.unpack_from('<I', track, p)[0]
        n = size // 3
        start = np.array(struct.unpack_from('<3i', track, p + 4), np.int64)
        steps = np.frombuffer(track, np.int8, 3 * (n - 1), p + 16).reshape(-1, 3).astype(np.int64)
        p += size + 13
        if n < 2:
            continue
        vox = np.vstack([start, start + np.cumsum(steps, axis=0)]) / 32.0
        points.append(vox @ T[:3, :3].T + T[:3, 3])
        offsets.append(offsets[-1] + n)
    pts = np.vstack(points) if points else np.zeros((0, 3))
    with open(out, 'wb') as f:
        np.array([len(offsets) - 1] + offsets, '<i8').tofile(f)
        pts.astype('<f8').tofile(f)

def matrix(name, a, ptype, big=False):
    a = np.asarray(a)
    rows, cols = (1, a.size) if a.ndim < 2 else a.shape
    end = '>' if big else '<'
    head = struct.pack(end + '5i', (1000 if big else 0) + 10 * ptype, rows, cols, 0, len(name) + 1)
    return head + name.encode() + b'\0' + np.asarray(a.T.ravel(), end + TYPES[ptype]).tobytes()

def track(lines):
    out = b''
    for pts in lines:
        pts = np.asarray(pts, np.int64)
        steps = np.diff(pts, axis=0)
        assert np.all(np.abs(steps) < 128)
        out += struct.pack('<I3i', 3 * len(pts), *pts[0]) + steps.astype(np.int8).tobytes()
    return np.frombuffer(out, np.uint8)

def walk(rng, n, start):
    return np.cumsum(np.vstack([start, rng.integers(-60, 61, (n - 1, 3))]), axis=0)

def write(name, parts, gz=True):
    b = b''.join(parts)
    open(name, 'wb').write(gzip.compress(b) if gz else b)
    parse(name, name + '.ref')

rng = np.random.default_rng(11)
lines = [walk(rng, n, s) for n, s in ((40, [1600, 2000, 1500]), (3, [-70, 30000, 7]),
                                      (1, [5, 5, 5]), (25, [3000, 100, 900]), (2, [0, 0, 0]))]
tt = track(lines)
angle = 0.3
oblique = np.array([[1.25 * np.cos(angle), -1.25 * np.sin(angle), 0, -80.5],
                    [1.25 * np.sin(angle), 1.25 * np.cos(angle), 0, -110.25],
                    [0, 0, 1.25, -60], [0, 0, 0, 1]])
dims, vs = [120, 140, 100], [1.25, 1.25, 1.25]
write('oblique.tt.gz', [matrix('dimension', dims, 2), matrix('voxel_size', vs, 1),
                        matrix('trans_to_mni', oblique.ravel(), 1), matrix('track', tt, 5),
                        matrix('report', np.frombuffer(b'made by a test\0', np.uint8), 5),
                        matrix('color', np.arange(5, dtype=np.int32), 2)])
write('native.tt.gz', [matrix('dimension', dims, 2), matrix('voxel_size', [2.0, 2.0, 2.5], 1),
                       matrix('track', tt, 5)])
write('plain.tt', [matrix('voxel_size', vs, 0), matrix('track', tt, 5),
                   matrix('trans_to_mni', oblique.ravel(), 0)], gz=False)
write('big_endian.tt.gz', [matrix('dimension', dims, 3, True), matrix('voxel_size', vs, 0, True),
                           matrix('trans_to_mni', oblique.ravel(), 0, True),
                           matrix('track', tt, 5, True)])
write('empty.tt.gz', [matrix('trans_to_mni', np.eye(4).ravel(), 1),
                      matrix('track', np.zeros(0, np.uint8), 5)])
for path in sys.argv[1:]:
    parse(path, os.path.basename(path) + '.ref')
)PY";

constexpr const char* kRealFile = "neuro/tracts/TR_S_R.tt.gz";

bool have_numpy() {
  static const bool ok =
      std::system("/usr/bin/python3 -c 'import numpy, gzip, struct' >/dev/null 2>&1") == 0;
  return ok;
}

struct Reference {
  std::vector<int64_t> offsets;
  std::vector<double> points;  // RAS
};

Reference read_reference(const std::filesystem::path& file) {
  const std::string bytes = read_bytes(file);
  Reference r;
  if (bytes.size() < 16) {
    ADD_FAILURE() << "no reference " << file;
    return r;
  }
  int64_t count = 0;
  std::memcpy(&count, bytes.data(), 8);
  r.offsets.resize(static_cast<size_t>(count) + 1);
  std::memcpy(r.offsets.data(), bytes.data() + 8, r.offsets.size() * 8);
  const size_t at = 8 + r.offsets.size() * 8;
  r.points.resize((bytes.size() - at) / 8);
  std::memcpy(r.points.data(), bytes.data() + at, r.points.size() * 8);
  return r;
}

// Streamlines equal the reference's, point by point, after RAS to LPS.
void expect_matches(const Streamlines& s, const Reference& r, const std::string& name) {
  ASSERT_EQ(s.offsets.size(), r.offsets.size()) << name;
  for (size_t i = 0; i < r.offsets.size(); ++i)
    ASSERT_EQ(s.offsets[i], static_cast<uint64_t>(r.offsets[i])) << name << " offset " << i;
  ASSERT_EQ(s.points.size() * 3, r.points.size()) << name;
  double worst = 0.0;
  for (size_t i = 0; i < s.points.size(); ++i) {
    worst = std::max({worst, std::abs(s.points[i].x + r.points[3 * i]),
                      std::abs(s.points[i].y + r.points[3 * i + 1]),
                      std::abs(s.points[i].z - r.points[3 * i + 2])});
  }
  EXPECT_LE(worst, 1e-4) << name << ": largest difference in mm";
}

bool contains(const std::vector<std::string>& notes, const std::string& part) {
  for (const std::string& n : notes)
    if (n.find(part) != std::string::npos) return true;
  return false;
}

class TtFiles : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    if (!have_numpy()) return;
    dir_ = new test::TempDir;
    write_bytes(*dir_ / "tt.py", kTtScript);
    std::string command = "cd '" + dir_->path().string() + "' && /usr/bin/python3 tt.py";
    if (std::filesystem::exists(test::shared_data(kRealFile)))
      command += " '" + test::shared_data(kRealFile).string() + "'";
    ok_ = std::system((command + " >tt.log 2>&1").c_str()) == 0;
  }
  static void TearDownTestSuite() {
    delete dir_;
    dir_ = nullptr;
  }
  void SetUp() override {
    if (!have_numpy()) GTEST_SKIP() << "/usr/bin/python3 with numpy is not available";
    ASSERT_TRUE(ok_) << "the Python script failed:\n" << read_bytes(*dir_ / "tt.log");
  }
  static std::filesystem::path file(const std::string& name) { return *dir_ / name; }

 private:
  inline static test::TempDir* dir_ = nullptr;
  inline static bool ok_ = false;
};

TEST_F(TtFiles, RealTractMatchesTheReferenceInsideTheMniBrain) {
  SKIP_WITHOUT_SHARED_DATA(kRealFile);
  std::vector<std::string> notes;
  const Streamlines s = detail::read_tt(test::shared_data(kRealFile), notes);
  expect_matches(s, read_reference(file("TR_S_R.tt.gz.ref")), kRealFile);
  EXPECT_GT(s.count(), 100u);
  size_t outside = 0;
  double min_x = 1e9;
  for (const glm::vec3& p : s.points) {
    const double x = -p.x, y = -p.y, z = p.z;  // back to RAS, the MNI box's space
    outside += !(x > -90 && x < 90 && y > -126 && y < 90 && z > -72 && z < 108);
    min_x = std::min(min_x, x);
  }
  EXPECT_EQ(outside, 0u) << "points outside the MNI brain box";
  EXPECT_GT(min_x, 0.0) << "a right-hemisphere tract lies at RAS x > 0";
  EXPECT_TRUE(s.point_values.empty() && s.streamline_values.empty());
}

TEST_F(TtFiles, FixturesMatchTheReference) {
  for (const char* name : {"oblique.tt.gz", "native.tt.gz", "plain.tt", "big_endian.tt.gz"}) {
    std::vector<std::string> notes;
    const Streamlines s = detail::read_tt(file(name), notes);
    expect_matches(s, read_reference(file(std::string(name) + ".ref")), name);
    EXPECT_EQ(s.count(), 4u) << name;  // the 1-point streamline is left out
    EXPECT_TRUE(contains(notes, "1 streamlines of fewer than 2 points left out")) << name;
  }
}

TEST_F(TtFiles, NotesSayWhatWasChosen) {
  std::vector<std::string> notes;
  detail::read_tt(file("oblique.tt.gz"), notes);
  EXPECT_TRUE(contains(notes, "matrices left unread: color"));
  EXPECT_FALSE(contains(notes, "no trans_to_mni"));
  notes.clear();
  detail::read_tt(file("native.tt.gz"), notes);
  EXPECT_TRUE(contains(notes, "no trans_to_mni"));
  notes.clear();
  const Streamlines empty = detail::read_tt(file("empty.tt.gz"), notes);
  EXPECT_EQ(empty.count(), 0u);
  EXPECT_TRUE(empty.points.empty());
  EXPECT_TRUE(contains(notes, "no streamlines"));
}

// A MATLAB v4 matrix, little-endian unless `type` says otherwise.
std::string matrix(const std::string& name, int32_t type, int32_t rows, int32_t cols,
                   const std::string& data, int32_t name_bytes = -1) {
  std::string out(20, '\0');
  const int32_t head[5] = {type, rows, cols, 0,
                           name_bytes < 0 ? static_cast<int32_t>(name.size() + 1) : name_bytes};
  std::memcpy(out.data(), head, 20);
  return out + name + '\0' + data;
}

template <class T>
std::string values(std::initializer_list<T> v) {
  std::string out(v.size() * sizeof(T), '\0');
  std::memcpy(out.data(), std::data(v), out.size());
  return out;
}

std::string bytes_matrix(const std::string& name, const std::string& data) {
  return matrix(name, 50, 1, static_cast<int32_t>(data.size()), data);
}

// One streamline record: its size field, first point, then `steps` bytes.
std::string record(uint32_t size, int32_t x, int32_t y, int32_t z, const std::string& steps) {
  std::string out(16, '\0');
  std::memcpy(out.data(), &size, 4);
  const int32_t p[3] = {x, y, z};
  std::memcpy(out.data() + 4, p, 12);
  return out + steps;
}

const std::string kIdentity = matrix(
    "trans_to_mni", 10, 1, 16, values<float>({1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1}));
const std::string kGoodTrack = bytes_matrix("track", record(6, 32, 64, 96, "\x01\x02\x03"));

std::string gz(const std::string& raw) {
  std::ostringstream out;
  detail::gzip({reinterpret_cast<const uint8_t*>(raw.data()), raw.size()}, out, 6, "test");
  return out.str();
}

TEST(TtReader, ReadsAHandMadeFile) {
  test::TempDir dir;
  std::vector<std::string> notes;
  const Streamlines s = detail::read_tt(dir.write("hand.tt.gz", gz(kIdentity + kGoodTrack)), notes);
  ASSERT_EQ(s.count(), 1u);
  ASSERT_EQ(s.points.size(), 2u);
  EXPECT_EQ(s.points[0], glm::vec3(-1.0f, -2.0f, 3.0f));  // (1, 2, 3) RAS to LPS
  EXPECT_EQ(s.points[1], glm::vec3(-1.03125f, -2.0625f, 3.09375f));
}

TEST(TtReader, RefusesDamagedFiles) {
  test::TempDir dir;
  std::vector<std::string> notes;
  auto refused = [&](const std::string& name, const std::string& bytes,
                     std::initializer_list<std::string> fragments) {
    const std::filesystem::path f = dir.write(name, bytes);
    std::vector<std::string> parts(fragments);
    parts.push_back(f.string());
    const std::string message = test::error_of([&] { detail::read_tt(f, notes); });
    for (const std::string& part : parts)
      EXPECT_NE(message.find(part), std::string::npos) << name << ": " << message;
  };
  const std::string whole = gz(kIdentity + kGoodTrack);
  refused("truncated.tt.gz", whole.substr(0, whole.size() / 2), {"truncated"});
  refused("header_cut.tt.gz", gz(kIdentity.substr(0, 12)), {"ends inside the header of matrix 0"});
  refused("lying_matrix.tt.gz", gz(kIdentity + matrix("track", 50, 1, 1000000000, "\x03")),
          {"matrix 'track' claims 1 x 1000000000 values", "left"});
  refused("lying_rows.tt.gz", gz(matrix("track", 50, 2147483647, 2147483647, "")),
          {"matrix 'track' claims 2147483647 x 2147483647"});
  refused("negative.tt.gz", gz(matrix("track", 50, -1, 3, "")), {"claims -1 x 3"});
  refused("bad_type.tt.gz", gz(matrix("track", 77, 1, 1, "x")), {"type 77", "MOPT"});
  refused("vax.tt.gz", gz(matrix("track", 2050, 1, 1, "x")), {"VAX"});
  refused("long_name.tt.gz", gz(matrix("track", 50, 1, 1, "x", 1 << 20)), {"name of 1048576"});
  refused("unterminated.tt.gz", gz(matrix("track", 50, 1, 1, "xy", 5)), {"does not end in a 0"});
  refused("twice.tt.gz", gz(kIdentity + kGoodTrack + kGoodTrack), {"'track' appears twice"});
  refused("no_track.tt.gz", gz(kIdentity), {"no matrix 'track'"});
  refused("double_track.tt.gz", gz(kIdentity + matrix("track", 0, 1, 1, values<double>({1}))),
          {"not the uint8 bytes"});
  refused("lying_record.tt.gz", gz(kIdentity + bytes_matrix("track", record(3000, 0, 0, 0, "ab"))),
          {"streamline 0 at byte 0 claims 1000 points"});
  refused("huge_record.tt.gz",
          gz(kIdentity + bytes_matrix("track", record(0xFFFFFFFF, 0, 0, 0, "ab"))),
          {"streamline 0 at byte 0 claims 1431655765 points"});
  refused(
      "second_record.tt.gz",
      gz(kIdentity + bytes_matrix("track", record(6, 0, 0, 0, "abc") + record(9, 0, 0, 0, "abc"))),
      {"streamline 1 at byte 19 claims 3 points"});
  refused("tail.tt.gz", gz(kIdentity + bytes_matrix("track", record(6, 0, 0, 0, "abc") + "xyz")),
          {"streamline 1 at byte 19 has 3 bytes"});
  refused("zero_size.tt.gz", gz(kIdentity + bytes_matrix("track", record(0, 0, 0, 0, ""))),
          {"size of 0 bytes"});
  refused("singular.tt.gz",
          gz(matrix("trans_to_mni", 10, 1, 16,
                    values<float>({1, 0, 0, 0, 2, 0, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1})) +
             kGoodTrack),
          {"trans_to_mni is singular"});
  refused("projective.tt.gz",
          gz(matrix("trans_to_mni", 10, 1, 16,
                    values<float>({1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 1, 1})) +
             kGoodTrack),
          {"last row is 0 0 1 1"});
  refused("nan_affine.tt.gz",
          gz(matrix("trans_to_mni", 10, 1, 16,
                    values<float>({NAN, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1})) +
             kGoodTrack),
          {"not finite"});
  refused("short_affine.tt.gz",
          gz(matrix("trans_to_mni", 10, 1, 9, std::string(36, '\0')) + kGoodTrack),
          {"'trans_to_mni' holds 1 x 9 values, not 16"});
  refused("text_affine.tt.gz",
          gz(matrix("trans_to_mni", 51, 1, 16, std::string(16, 'a')) + kGoodTrack),
          {"'trans_to_mni' is text"});
  refused("unplaced.tt.gz", gz(kGoodTrack), {"no trans_to_mni, and no dimension and voxel_size"});
  refused("bad_voxels.tt.gz",
          gz(matrix("voxel_size", 10, 1, 3, values<float>({1, 0, 1})) +
             matrix("dimension", 20, 1, 3, values<int32_t>({10, 10, 10})) + kGoodTrack),
          {"voxel_size 1 0 1"});
  refused("not_gzip_nor_mat.tt.gz", std::string("hello, this is not a tractogram"), {"type field"});
  std::string corrupt = whole;
  corrupt[corrupt.size() / 2] ^= 0x55;
  corrupt[corrupt.size() / 2 + 1] ^= 0x55;
  const std::filesystem::path f = dir.write("corrupt.tt.gz", corrupt);
  const std::string message = test::error_of([&] { detail::read_tt(f, notes); });
  EXPECT_NE(message.find(f.string()), std::string::npos) << message;
  EXPECT_NE(message, "(no error)");
}

TEST(TtReader, DropsStreamlinesThatLeaveTheFloats) {
  test::TempDir dir;
  std::vector<std::string> notes;
  const std::string huge =
      matrix("trans_to_mni", 0, 1, 16,
             values<double>({1e300, 0, 0, 0, 0, 1e300, 0, 0, 0, 0, 1e300, 0, 0, 0, 0, 1}));
  const std::string track = bytes_matrix(
      "track", record(6, 0, 0, 0, "\x01\x01\x01") + record(6, 1 << 30, 0, 0, "\x01\x01\x01"));
  const Streamlines s = detail::read_tt(dir.write("huge.tt.gz", gz(huge + track)), notes);
  EXPECT_EQ(s.count(), 0u);
  EXPECT_TRUE(s.points.empty());
  EXPECT_TRUE(contains(notes, "2 streamlines left out")) << ::testing::PrintToString(notes);
}

struct LimitsGuard {
  ~LimitsGuard() { set_input_limits({}); }
};

TEST(TtReader, InflatesNoMoreThanTheMemoryBudget) {
  test::TempDir dir;
  LimitsGuard guard;
  set_input_limits({uint64_t{4} << 20, false});
  std::vector<std::string> notes;
  const std::string filler = bytes_matrix("filler", std::string(size_t{16} << 20, '\0'));
  const std::filesystem::path f = dir.write("bomb.tt.gz", gz(kIdentity + filler + kGoodTrack));
  test::expect_error([&] { detail::read_tt(f, notes); }, {f.string(), "memory budget"});
}

}  // namespace
}  // namespace imx
