// TRX reader (io/streamlines/trx.hpp) against Python's own reading of the same files: a script
// (/usr/bin/python3, zipfile and numpy) writes TRX fixtures, folders and zip archives (stored,
// deflated, zip64) with float16/32/64 positions, both offsets forms, dpv, dps, groups and group
// colours, and for each a reference of what it holds, read back through zipfile and numpy alone;
// and malformed TRX files, each refused with an error naming the member at fault.
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <map>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "core/colour.hpp"
#include "intermix/error.hpp"
#include "io/streamlines/trx.hpp"
#include "shared_data.hpp"
#include "temp_dir.hpp"

namespace imx::test {
namespace {

bool have_numpy() {
  static const bool ok = std::system("/usr/bin/python3 -c 'import numpy' >/dev/null 2>&1") == 0;
  return ok;
}

bool have_nibabel_streamlines() {
  static const bool ok =
      std::system("/usr/bin/python3 -c 'import nibabel.streamlines, numpy' >/dev/null 2>&1") == 0;
  return ok;
}

// The reference reader and the fixture writer. ref(src, out) reads a TRX (zip or folder) with
// zipfile and numpy as trx-python lays it out, drops the streamlines with fewer than 2 points or
// non-finite points, and writes records (u32 name length, name, u64 count, count float64):
// "positions" (RAS, x y z per point), "offsets", "dpv:NAME", "dps:NAME" (NAME_c per column when
// an array has several), "group:NAME" (its kept members, renumbered, sorted) and "color:GROUP".
const char* kScript = R"PY(
import io, json, os, struct, sys, zipfile, zlib
import numpy as np

DT = {'int8': '<i1', 'int16': '<i2', 'int32': '<i4', 'int64': '<i8', 'uint8': '<u1',
      'uint16': '<u2', 'uint32': '<u4', 'uint64': '<u8', 'float16': '<f2', 'float32': '<f4',
      'float64': '<f8', 'bit': '<u1'}

def members_of(src):
    files = {}
    if os.path.isdir(src):
        for root, _, names in os.walk(src):
            for n in names:
                p = os.path.join(root, n)
                files[os.path.relpath(p, src).replace(os.sep, '/')] = open(p, 'rb').read()
    else:
        with zipfile.ZipFile(src) as z:
            for i in z.infolist():
                if not i.is_dir():
                    files[i.filename] = z.read(i)
    return files

def ref(src, out):
    files = members_of(src)
    hdr = json.loads(files['header.json'])
    n, v = hdr['NB_STREAMLINES'], hdr['NB_VERTICES']
    arrays = {}
    for name, data in files.items():
        parts = name.split('/')
        dots = parts[-1].split('.')
        if dots[-1] not in DT:
            continue
        cols = int(dots[1]) if len(dots) == 3 else 1
        arrays[name] = (parts[:-1], dots[0], cols, np.frombuffer(data, DT[dots[-1]]), dots[-1])
    # An array whose size disagrees with the header (trx-python refuses the file): its name.
    for key, (folder, base, cols, a, dtype) in sorted(arrays.items()):
        rows = {'dpv': v, 'dps': n}.get(folder[0] if folder else '', None)
        if rows is not None and len(a) != rows * cols:
            open(out + '.bad', 'w').write(key)
            return
    pos = next(a for k, a in arrays.items() if a[0] == [] and a[1] == 'positions')
    pos = pos[3].astype(np.float64).reshape(-1, 3)
    off = next(a for k, a in arrays.items() if a[0] == [] and a[1] == 'offsets')[3].astype(np.int64)
    if len(off) == n:
        off = np.append(off, v)
    lengths = np.diff(off)
    keep = np.array([lengths[i] >= 2 and np.isfinite(pos[off[i]:off[i + 1]]).all()
                     for i in range(n)], dtype=bool)
    point_keep = np.zeros(len(pos), dtype=bool)  # vertices past the last offset: in none
    point_keep[:off[-1]] = np.repeat(keep, lengths)
    new_index = np.cumsum(keep) - 1
    records = [('positions', pos[point_keep].ravel()),
               ('offsets', np.concatenate([[0], np.cumsum(lengths[keep])]))]
    for key in sorted(arrays):
        folder, base, cols, a, dtype = arrays[key]
        if folder in (['dpv'], ['dps']):
            a = a.astype(np.float64).reshape(-1, cols)
            a = a[point_keep] if folder == ['dpv'] else a[keep]
            for c in range(cols):
                records.append((folder[0] + ':' + (base if cols == 1 else '%s_%d' % (base, c)), a[:, c]))
        elif folder == ['groups']:
            m = np.unique(a.astype(np.int64))
            records.append(('group:' + base, new_index[m[keep[m]]]))
        elif len(folder) == 2 and folder[0] == 'dpg' and cols == 3 and 'color' in base.lower():
            c = a.astype(np.float64)
            if dtype.startswith('float') and c.max() <= 1:
                records.append(('color:' + folder[1], c))
            else:
                records.append(('color:' + folder[1], c / 255))
    with open(out, 'wb') as f:
        for name, values in records:
            values = np.asarray(values, dtype='<f8')
            f.write(struct.pack('<I', len(name.encode())) + name.encode())
            f.write(struct.pack('<Q', len(values)) + values.tobytes())

def header(n, v, **drop):
    h = {'DIMENSIONS': [10, 11, 12], 'NB_STREAMLINES': n, 'NB_VERTICES': v,
         'VOXEL_TO_RASMM': [[2.0, 0, 0, -10], [0, 2.0, 0, -12], [0, 0, 2.0, 5], [0, 0, 0, 1]]}
    for k in drop:
        del h[k]
    return json.dumps(h).encode()

# Five streamlines (lengths 3, 5, 1, 4, 6): the third has one point, the fourth a NaN.
def tractogram(pos_dtype='float32', off_dtype='uint64', sentinel=True):
    rng = np.random.default_rng(7)
    lengths = np.array([3, 5, 1, 4, 6])
    n, v = len(lengths), int(lengths.sum())
    pos = (rng.normal(size=(v, 3)) * 40 + [5, -7, 11]).astype(np.float64)
    pos[3 + 5 + 1 + 2, 1] = np.nan
    off = np.concatenate([[0], np.cumsum(lengths)])
    if not sentinel:
        off = off[:-1]
    m = {'header.json': header(n, v),
         'positions.3.' + pos_dtype: pos.astype(DT[pos_dtype]).tobytes(),
         'offsets.' + off_dtype: off.astype(DT[off_dtype]).tobytes(),
         'dpv/fa.float16': rng.random(v).astype('<f2').tobytes(),
         'dpv/rgb.3.uint8': rng.integers(0, 256, size=(v, 3)).astype('<u1').tobytes(),
         'dpv/effect   .float32': rng.normal(size=v).astype('<f4').tobytes(),
         'dps/weight.float64': rng.normal(size=n).astype('<f8').tobytes(),
         'dps/pair.2.int16': rng.integers(-900, 900, size=(n, 2)).astype('<i2').tobytes(),
         'dps/algo.json': b'{"note": "not an array"}',
         'groups/CC.uint32': np.array([0, 1, 2, 4], '<u4').tobytes(),
         'groups/AF.int64': np.array([4, 3, 1], '<i8').tobytes(),
         'dpg/CC/color.3.uint8': np.array([255, 128, 0], '<u1').tobytes(),
         'dpg/CC/volume.uint32': np.array([12], '<u4').tobytes(),
         'dpg/AF/shuffle_colors.3.float32': np.array([0.25, 0.5, 1.0], '<f4').tobytes(),
         'readme.txt': b'ignored'}
    return m

def write_folder(path, members):
    for name, data in members.items():
        p = os.path.join(path, *name.split('/'))
        os.makedirs(os.path.dirname(p), exist_ok=True)
        open(p, 'wb').write(data)

def write_zip(path, members, method=zipfile.ZIP_STORED):
    with zipfile.ZipFile(path, 'w', method) as z:
        for name, data in members.items():
            z.writestr(name, data)

# A stored zip whose every size and offset lives in zip64 extra fields, with the zip64 end
# records, as a writer of files past 4 GiB makes it.
def write_zip64(path, members):
    out, central = bytearray(), bytearray()
    for name, data in members.items():
        nb, crc, offset = name.encode(), zlib.crc32(data), len(out)
        local_extra = struct.pack('<HHQQ', 1, 16, len(data), len(data))
        out += struct.pack('<IHHHHHIIIHH', 0x04034b50, 45, 0, 0, 0, 0, crc, 0xffffffff,
                           0xffffffff, len(nb), len(local_extra)) + nb + local_extra + data
        extra = struct.pack('<HHQQQ', 1, 24, len(data), len(data), offset)
        central += struct.pack('<IHHHHHHIIIHHHHHII', 0x02014b50, 45, 45, 0, 0, 0, 0, crc,
                               0xffffffff, 0xffffffff, len(nb), len(extra), 0, 0, 0, 0,
                               0xffffffff) + nb + extra
    cd_offset, count = len(out), len(members)
    out += central
    eocd64 = len(out)
    out += struct.pack('<IQHHIIQQQQ', 0x06064b50, 44, 45, 45, 0, 0, count, count, len(central),
                       cd_offset)
    out += struct.pack('<IIQI', 0x07064b50, 0, eocd64, 1)
    out += struct.pack('<IHHHHIIH', 0x06054b50, 0, 0, 0xffff, 0xffff, 0xffffffff, 0xffffffff, 0)
    open(path, 'wb').write(out)

good = {
    'folder_f32': ('folder', tractogram()),
    'stored_f16.trx': ('stored', tractogram('float16', 'uint32', sentinel=False)),
    'deflated_f64.trx': ('deflated', tractogram('float64', 'uint64')),
    'zip64_f32.trx': ('zip64', tractogram('float32', 'uint32')),
}
for name, (kind, m) in good.items():
    if kind == 'folder':
        write_folder(name, m)
    elif kind == 'zip64':
        write_zip64(name, m)
    else:
        write_zip(name, m, zipfile.ZIP_STORED if kind == 'stored' else zipfile.ZIP_DEFLATED)
    ref(name, name + '.ref')
for shared in sys.argv[1:]:
    ref(shared, os.path.basename(shared) + '.ref')

# Malformed: each a copy of a good tractogram with one thing wrong.
def bad(name, change, method=zipfile.ZIP_DEFLATED):
    m = tractogram()
    change(m)
    write_zip(name, m, method)

def set_(key, value):
    return lambda m: m.__setitem__(key, value)

def drop(key):
    return lambda m: m.pop(key)

bad('short_positions.trx', lambda m: m.__setitem__('positions.3.float32', m['positions.3.float32'][:-12]))
bad('short_dpv.trx', lambda m: m.__setitem__('dpv/fa.float16', m['dpv/fa.float16'][:-2]))
bad('long_dps.trx', lambda m: m.__setitem__('dps/weight.float64', m['dps/weight.float64'] + bytes(8)))
bad('dpv_columns.trx', lambda m: m.__setitem__('dpv/rgb.2.uint8', m.pop('dpv/rgb.3.uint8')))
bad('descending_offsets.trx', set_('offsets.uint64', np.array([0, 3, 9, 8, 12, 19], '<u8').tobytes()))
bad('first_offset.trx', set_('offsets.uint64', np.array([1, 3, 8, 9, 13, 19], '<u8').tobytes()))
bad('offset_past_end.trx', set_('offsets.uint64', np.array([0, 3, 8, 9, 20, 19], '<u8').tobytes()))
bad('sentinel.trx', set_('offsets.uint64', np.array([0, 3, 8, 9, 13, 20], '<u8').tobytes()))
# Good, as trx-python reads it: the last offset short of NB_VERTICES leaves one vertex unused.
unused = tractogram()
unused['offsets.uint64'] = np.array([0, 3, 8, 9, 13, 18], '<u8').tobytes()
write_zip('unused_vertex.trx', unused)
ref('unused_vertex.trx', 'unused_vertex.trx.ref')
bad('offsets_size.trx', set_('offsets.uint64', np.array([0, 3, 8], '<u8').tobytes()))
bad('float_offsets.trx', lambda m: m.__setitem__('offsets.float32', np.array([0, 3, 8, 9, 13, 19], '<f4').tobytes()) or m.pop('offsets.uint64'))
bad('no_vertices.trx', set_('header.json', header(5, 19, NB_VERTICES=1)))
bad('no_affine.trx', set_('header.json', header(5, 19, VOXEL_TO_RASMM=1)))
bad('wrong_count.trx', set_('header.json', header(6, 19)))
bad('not_json.trx', set_('header.json', b'{"NB_STREAMLINES": 5,'))
bad('deep_json.trx', set_('header.json', b'[' * 100000))
bad('no_positions.trx', drop('positions.3.float32'))
bad('int_positions.trx', lambda m: m.__setitem__('positions.3.int32', np.zeros(57, '<i4').tobytes()) or m.pop('positions.3.float32'))
bad('two_positions.trx', set_('positions.3.float16', np.zeros(57, '<f2').tobytes()))
bad('group_range.trx', set_('groups/CC.uint32', np.array([0, 5], '<u4').tobytes()))
bad('negative_group.trx', set_('groups/AF.int64', np.array([-1], '<i8').tobytes()))
bad('undeclared_dpg.trx', set_('dpg/SLF/color.3.uint8', bytes(3)))
bad('dotted_name.trx', set_('dpv/f.a.b.float32', bytes(76)))
bad('zero_columns.trx', set_('dps/w.0.float32', bytes(0)))
open('not_a_zip.trx', 'wb').write(b'PK\x03\x04' + bytes(range(256)) * 4)
whole = open('deflated_f64.trx', 'rb').read()
open('truncated.trx', 'wb').write(whole[:len(whole) // 2])

# Zip bombs. claims_more: positions inflate to 64 MiB of zeros, and the directory says so.
bomb = bytes(64 << 20)
bad('claims_more.trx', set_('positions.3.float32', bomb))
# lies_less: the same data, but the directory and local header claim the 228 bytes
# NB_VERTICES = 19 needs (and their CRC).
m = tractogram()
m['positions.3.float32'] = bomb
write_zip('lies_less.trx', m, zipfile.ZIP_DEFLATED)
data = bytearray(open('lies_less.trx', 'rb').read())
with zipfile.ZipFile(io.BytesIO(bytes(data))) as z:
    info = z.getinfo('positions.3.float32')
crc = zlib.crc32(bomb[:228])
pos = 0
while True:
    pos = data.index(b'PK\x01\x02', pos)
    n = struct.unpack_from('<H', data, pos + 28)[0]
    if data[pos + 46:pos + 46 + n] == b'positions.3.float32':
        struct.pack_into('<III', data, pos + 16, crc, info.compress_size, 228)
        break
    pos += 4
struct.pack_into('<III', data, info.header_offset + 14, crc, info.compress_size, 228)
open('lies_less.trx', 'wb').write(data)
)PY";

using Records = std::map<std::string, std::vector<double>>;

Records read_records(const std::filesystem::path& file) {
  const std::string bytes = read_bytes(file);
  Records r;
  size_t at = 0;
  while (at + 4 <= bytes.size()) {
    uint32_t name_size = 0;
    std::memcpy(&name_size, bytes.data() + at, 4);
    const std::string name = bytes.substr(at + 4, name_size);
    at += 4 + name_size;
    uint64_t count = 0;
    std::memcpy(&count, bytes.data() + at, 8);
    at += 8;
    std::vector<double>& values = r[name];
    values.resize(count);
    std::memcpy(values.data(), bytes.data() + at, count * 8);
    at += count * 8;
  }
  if (r.empty()) ADD_FAILURE() << "no reference in " << file;
  return r;
}

const StreamlineValues* find_values(const std::vector<StreamlineValues>& all,
                                    const std::string& name) {
  for (const StreamlineValues& v : all)
    if (v.name == name) return &v;
  return nullptr;
}

// `s` holds what Python read: the same points (LPS: x and y negated), offsets, values, groups
// and colours, and nothing else. `tolerance` is for float64 positions rounded to float.
void expect_reference(const Streamlines& s, const Records& r, const std::string& what,
                      double tolerance = 0.0) {
  const std::vector<double>& pos = r.at("positions");
  ASSERT_EQ(s.points.size() * 3, pos.size()) << what;
  int wrong = 0;
  for (size_t i = 0; i < s.points.size(); ++i) {
    const double want[3] = {-pos[3 * i], -pos[3 * i + 1], pos[3 * i + 2]};
    for (int c = 0; c < 3; ++c)
      if (std::abs(s.points[i][c] - want[c]) > tolerance && wrong++ < 5)
        ADD_FAILURE() << what << ": point " << i << " axis " << c << " is " << s.points[i][c]
                      << ", Python reads " << want[c];
  }
  EXPECT_EQ(wrong, 0) << what;
  const std::vector<double>& off = r.at("offsets");
  ASSERT_EQ(s.offsets.size(), off.size()) << what;
  for (size_t i = 0; i < off.size(); ++i)
    EXPECT_EQ(s.offsets[i], off[i]) << what << " offset " << i;
  size_t dpv = 0, dps = 0, groups = 0;
  for (const auto& [key, values] : r) {
    const std::string kind = key.substr(0, key.find(':')), name = key.substr(key.find(':') + 1);
    if (kind == "dpv" || kind == "dps") {
      const StreamlineValues* v =
          find_values(kind == "dpv" ? s.point_values : s.streamline_values, name);
      ++(kind == "dpv" ? dpv : dps);
      ASSERT_NE(v, nullptr) << what << ": no " << key;
      ASSERT_EQ(v->values.size(), values.size()) << what << ": " << key;
      for (size_t i = 0; i < values.size(); ++i)
        EXPECT_NEAR(v->values[i], values[i], 1e-6 * std::max(1.0, std::abs(values[i])))
            << what << ": " << key << "[" << i << "]";
    } else if (kind == "group" || kind == "color") {
      const StreamlineGroup* g = nullptr;
      for (const StreamlineGroup& candidate : s.groups)
        if (candidate.name == name) g = &candidate;
      ASSERT_NE(g, nullptr) << what << ": no group " << name;
      if (kind == "group") {
        ++groups;
        EXPECT_EQ(std::vector<double>(g->members.begin(), g->members.end()), values)
            << what << ": " << key;
      } else {
        // The file's display colour (Python's value), decoded once as it is read.
        ASSERT_TRUE(g->color.has_value()) << what << ": " << key;
        for (int c = 0; c < 3; ++c)
          EXPECT_NEAR((*g->color)[c], srgb_decode(static_cast<float>(values[c])), 1e-6)
              << what << key;
      }
    }
  }
  EXPECT_EQ(s.point_values.size(), dpv) << what;
  EXPECT_EQ(s.streamline_values.size(), dps) << what;
  EXPECT_EQ(s.groups.size(), groups) << what;
  for (const StreamlineGroup& g : s.groups) {
    if (g.color) {
      EXPECT_TRUE(r.count("color:" + g.name)) << what << ": colour of " << g.name;
    }
  }
}

class Trx : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    if (!have_numpy()) return;
    dir_ = new TempDir;
    write_bytes(*dir_ / "make.py", kScript);
    std::string command = "cd '" + dir_->path().string() + "' && /usr/bin/python3 make.py";
    for (const char* shared : {"neuro/tracts/colby.trx", "neuro/tracts/dpsv.trx"})
      if (std::filesystem::exists(shared_data(shared)))
        command += " '" + shared_data(shared).string() + "'";
    ok_ = std::system((command + " >make.log 2>&1").c_str()) == 0;
  }
  static void TearDownTestSuite() {
    delete dir_;
    dir_ = nullptr;
  }
  void SetUp() override {
    if (!have_numpy()) GTEST_SKIP() << "/usr/bin/python3 with numpy is not available";
    ASSERT_TRUE(ok_) << "the fixture script failed:\n" << read_bytes(*dir_ / "make.log");
  }
  static std::filesystem::path file(const std::string& name) { return *dir_ / name; }

  // The error reading `name` gives; a failure when it reads.
  static std::string error_of(const std::string& name) {
    std::vector<std::string> notes;
    try {
      detail::read_trx(file(name), notes);
    } catch (const Error& e) {
      return e.what();
    }
    ADD_FAILURE() << name << " was read without an error";
    return {};
  }

 private:
  inline static TempDir* dir_ = nullptr;
  inline static bool ok_ = false;
};

TEST_F(Trx, FolderFloat32MatchesPython) {
  std::vector<std::string> notes;
  const Streamlines s = detail::read_trx(file("folder_f32"), notes);
  expect_reference(s, read_records(file("folder_f32.ref")), "folder_f32");
  // The one-point and the NaN streamline dropped: 3 left, groups renumbered.
  EXPECT_EQ(s.count(), 3u);
  ASSERT_EQ(s.groups.size(), 2u);
  std::string all;
  for (const std::string& n : notes) all += n + "\n";
  EXPECT_NE(all.find("fewer than 2 points"), std::string::npos) << all;
  EXPECT_NE(all.find("NaN"), std::string::npos) << all;
  EXPECT_NE(all.find("readme.txt"), std::string::npos) << all;
  EXPECT_NE(all.find("dpg/CC/volume.uint32"), std::string::npos) << all;
  // Multi-column arrays: one value array per column.
  EXPECT_NE(find_values(s.point_values, "rgb_2"), nullptr);
  EXPECT_NE(find_values(s.streamline_values, "pair_1"), nullptr);
}

TEST_F(Trx, StoredZipFloat16WithoutSentinelMatchesPython) {
  std::vector<std::string> notes;
  const Streamlines s = detail::read_trx(file("stored_f16.trx"), notes);
  expect_reference(s, read_records(file("stored_f16.trx.ref")), "stored_f16");  // exact
}

TEST_F(Trx, DeflatedZipFloat64MatchesPython) {
  std::vector<std::string> notes;
  const Streamlines s = detail::read_trx(file("deflated_f64.trx"), notes);
  expect_reference(s, read_records(file("deflated_f64.trx.ref")), "deflated_f64", 1e-4);
}

TEST_F(Trx, Zip64MatchesPython) {
  std::vector<std::string> notes;
  const Streamlines s = detail::read_trx(file("zip64_f32.trx"), notes);
  expect_reference(s, read_records(file("zip64_f32.trx.ref")), "zip64_f32");
}

TEST_F(Trx, SharedFilesMatchPython) {
  SKIP_WITHOUT_SHARED_DATA("neuro/tracts/colby.trx", "neuro/tracts/dpsv.trx");
  for (const char* name : {"colby.trx", "dpsv.trx"}) {
    const std::filesystem::path trx = shared_data(std::string("neuro/tracts/") + name);
    std::vector<std::string> notes;
    if (std::filesystem::exists(file(std::string(name) + ".ref.bad"))) {
      // dpsv.trx: dps/DataSetID.float32 holds 460 values for NB_STREAMLINES = 459, which
      // trx-python refuses ("Wrong dps size/dimensionality"); this reader leaves that optional
      // array out, naming it, and reads the streamlines (as NiiVue shows them).
      const std::string member = read_bytes(file(std::string(name) + ".ref.bad"));
      const Streamlines s = detail::read_trx(trx, notes);
      EXPECT_GT(s.count(), 0u);
      std::string all;
      for (const std::string& n : notes) all += n + "\n";
      EXPECT_NE(all.find(member + " left out"), std::string::npos) << all;
      continue;
    }
    const Streamlines s = detail::read_trx(trx, notes);
    expect_reference(s, read_records(file(std::string(name) + ".ref")), name);
  }
}

// colby.trx and colby.trk hold the same two streamlines (float16 positions against the TRK's
// float32): nibabel's reading of the TRK agrees to float16's rounding, values exactly.
TEST_F(Trx, ColbyMatchesNibabelTrk) {
  SKIP_WITHOUT_SHARED_DATA("neuro/tracts/colby.trx", "neuro/tracts/colby.trk");
  if (!have_nibabel_streamlines()) GTEST_SKIP() << "no nibabel for /usr/bin/python3";
  const std::string out = (file("colby_trk.ref")).string();
  const std::string command =
      "/usr/bin/python3 -c \"import sys, numpy as np, nibabel as nib\n"
      "t = nib.streamlines.load(sys.argv[1])\n"
      "p = np.concatenate(list(t.streamlines)).astype('<f8')\n"
      "o = np.concatenate([[0], np.cumsum([len(s) for s in t.streamlines])]).astype('<f8')\n"
      "v = np.concatenate(list(t.tractogram.data_per_point['pval     '])).astype('<f8')\n"
      "open(sys.argv[2], 'wb').write(p.tobytes() + o.tobytes() + v.tobytes())\" '" +
      shared_data("neuro/tracts/colby.trk").string() + "' '" + out + "' 2>/dev/null";
  ASSERT_EQ(std::system(command.c_str()), 0);
  std::vector<std::string> notes;
  const Streamlines s = detail::read_trx(shared_data("neuro/tracts/colby.trx"), notes);
  const std::string bytes = read_bytes(out);
  const size_t n = s.points.size();
  ASSERT_EQ(bytes.size(), (3 * n + s.offsets.size() + n) * 8);
  std::vector<double> ref(bytes.size() / 8);
  std::memcpy(ref.data(), bytes.data(), bytes.size());
  for (size_t i = 0; i < n; ++i)
    for (int c = 0; c < 3; ++c) {
      const double want = (c < 2 ? -1.0 : 1.0) * ref[3 * i + c];
      // float16 keeps 11 significant bits: half a step is 2^-11 of the magnitude.
      EXPECT_NEAR(s.points[i][c], want, std::abs(want) / 2048 + 1e-6) << "point " << i;
    }
  for (size_t i = 0; i < s.offsets.size(); ++i) EXPECT_EQ(s.offsets[i], ref[3 * n + i]);
  const StreamlineValues* pval = find_values(s.point_values, "pval     ");
  ASSERT_NE(pval, nullptr);
  for (size_t i = 0; i < n; ++i)
    EXPECT_FLOAT_EQ(pval->values[i], ref[3 * n + s.offsets.size() + i]);
}

TEST_F(Trx, DisagreeingArraysNameTheMember) {
  const std::pair<const char*, std::vector<const char*>> cases[] = {
      {"short_positions.trx", {"positions.3.float32", "NB_VERTICES"}},
      {"offsets_size.trx", {"offsets.uint64", "NB_STREAMLINES"}},
      {"float_offsets.trx", {"offsets.float32", "integers"}},
      {"int_positions.trx", {"positions.3.int32", "int32"}},
      {"two_positions.trx", {"positions"}},
      {"dotted_name.trx", {"dpv/f.a.b.float32"}},
      {"zero_columns.trx", {"dps/w.0.float32", "column"}},
  };
  for (const auto& [name, words] : cases) {
    const std::string message = error_of(name);
    EXPECT_NE(message.find(name), std::string::npos) << message;
    for (const char* word : words) EXPECT_NE(message.find(word), std::string::npos) << message;
  }
}

// Optional data arrays that disagree with the counts are left out, each named in a note.
TEST_F(Trx, DisagreeingDataArraysAreLeftOutNamed) {
  // wrong_count.trx: a header of 6 streamlines whose offsets hold 6 + 1 entries is whole; its
  // 7-value dps array is what disagrees.
  const std::pair<const char*, const char*> cases[] = {{"short_dpv.trx", "dpv/fa.float16"},
                                                       {"long_dps.trx", "dps/weight.float64"},
                                                       {"dpv_columns.trx", "dpv/rgb.2.uint8"},
                                                       {"wrong_count.trx", "dps/weight.float64"}};
  for (const auto& [name, member] : cases) {
    std::vector<std::string> notes;
    const Streamlines s = detail::read_trx(file(name), notes);
    EXPECT_GT(s.count(), 0u) << name;
    std::string all;
    for (const std::string& n : notes) all += n + "\n";
    EXPECT_NE(all.find(std::string(member) + " left out"), std::string::npos) << all;
    for (const StreamlineValues& v : s.point_values) EXPECT_EQ(v.values.size(), s.points.size());
    for (const StreamlineValues& v : s.streamline_values) EXPECT_EQ(v.values.size(), s.count());
  }
}

TEST_F(Trx, BadOffsetsAreRefused) {
  EXPECT_NE(error_of("descending_offsets.trx").find("do not ascend"), std::string::npos);
  EXPECT_NE(error_of("first_offset.trx").find("not 0"), std::string::npos);
  EXPECT_NE(error_of("offset_past_end.trx").find("outside"), std::string::npos);
  EXPECT_NE(error_of("sentinel.trx").find("outside 0 .. NB_VERTICES = 19"), std::string::npos);
}

// dpsv.trx's last offset falls short of NB_VERTICES too: trx-python reads the streamlines the
// offsets give and leaves the rest of the vertices (and their dpv values) unused.
TEST_F(Trx, VerticesPastTheLastOffsetAreUnused) {
  std::vector<std::string> notes;
  const Streamlines s = detail::read_trx(file("unused_vertex.trx"), notes);
  expect_reference(s, read_records(file("unused_vertex.trx.ref")), "unused_vertex");
  std::string all;
  for (const std::string& n : notes) all += n + "\n";
  EXPECT_NE(all.find("1 vertex"), std::string::npos) << all;
}

TEST_F(Trx, BadHeadersAndGroupsAreRefused) {
  EXPECT_NE(error_of("no_vertices.trx").find("no NB_VERTICES key"), std::string::npos);
  EXPECT_NE(error_of("no_affine.trx").find("no VOXEL_TO_RASMM key"), std::string::npos);
  EXPECT_NE(error_of("not_json.trx").find("header.json: not valid JSON"), std::string::npos);
  EXPECT_NE(error_of("deep_json.trx").find("nested too deeply"), std::string::npos);
  EXPECT_NE(error_of("no_positions.trx").find("no positions"), std::string::npos);
  EXPECT_NE(error_of("group_range.trx").find("groups/CC.uint32"), std::string::npos);
  EXPECT_NE(error_of("negative_group.trx").find("groups/AF.int64"), std::string::npos);
  EXPECT_NE(error_of("undeclared_dpg.trx").find("dpg/SLF/color.3.uint8"), std::string::npos);
  EXPECT_NE(error_of("not_a_zip.trx").find("not a zip"), std::string::npos);
  EXPECT_FALSE(error_of("truncated.trx").empty());
}

// A deflated member claiming far more than NB_VERTICES allows is refused before inflating; one
// whose directory claims the right size while its data inflates to 64 MiB is read only up to
// that size, and refused.
TEST_F(Trx, ZipBombsAreRefusedWithoutInflating) {
  for (const char* name : {"claims_more.trx", "lies_less.trx"}) {
    const auto start = std::chrono::steady_clock::now();
    const std::string message = error_of(name);
    const double seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    EXPECT_NE(message.find("positions.3.float32"), std::string::npos) << message;
    EXPECT_LT(seconds, 0.05) << name << " took " << seconds << " s: inflated in full?";
  }
  EXPECT_NE(error_of("claims_more.trx").find(std::to_string(64 << 20)), std::string::npos);
  EXPECT_NE(error_of("lies_less.trx").find("inflates to more than the 228 bytes"),
            std::string::npos);
}

}  // namespace
}  // namespace imx::test
