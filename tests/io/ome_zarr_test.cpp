// OME-Zarr (NGFF 0.4, Zarr v2) volumes against zarr-python's own reading of the same files.
#include <cmath>
#include <string>

#include <gtest/gtest.h>

#include "expect_error.hpp"
#include "intermix/dicom.hpp"
#include "intermix/io.hpp"
#include "io/zarr/ome_zarr_reader.hpp"
#include "io/zarr/zarr_array.hpp"
#include "ome_zarr_files.hpp"
#include "reference_voxels.hpp"
#include "temp_dir.hpp"

namespace imx::detail {
namespace {

using test::expect_error;
using test::TempDir;

void expect_reference_voxels(const VolumeData& v, const std::filesystem::path& ref_file) {
  test::expect_reference_voxels(v, ref_file, "zarr");
}

TEST(OmeZarr, EveryDtypeReadsAsZarrDoes) {
  SKIP_WITHOUT_ZARR();
  TempDir dir;
  ASSERT_TRUE(test::run_zarr_python(dir, R"PY(
rng = np.random.default_rng(7)
for n, dt in enumerate(['<u2', '>f4', '|u1', '<i2', '<f8', '<i4', '<u4', '|i1', '>i2', '>u2',
                        '<f4', '>f8', '>i4', '<i8', '<u8']):
    info = np.iinfo(dt) if dt[1] in 'iu' else None
    if info is None:
        data = rng.normal(0, 1000, (5, 6, 7)).astype(dt)
    else:
        lo, hi = max(info.min, -2**40), min(info.max, 2**40)
        data = rng.integers(lo, hi, (5, 6, 7), endpoint=True).astype(dt)
    a = image(f'dt{n}.zarr', [data], chunks=[(2, 3, 4)], compressor=Zlib())
    ref(f'dt{n}.f64', a[0][...])
)PY"));
  const VoxelType storage[] = {VoxelType::u16, VoxelType::f32, VoxelType::u8,  VoxelType::i16,
                               VoxelType::f32, VoxelType::f32, VoxelType::f32, VoxelType::i16,
                               VoxelType::i16, VoxelType::u16, VoxelType::f32, VoxelType::f32,
                               VoxelType::f32, VoxelType::f32, VoxelType::f32};
  for (int n = 0; n < 15; ++n) {
    SCOPED_TRACE(n);
    const auto path = dir / ("dt" + std::to_string(n) + ".zarr");
    const VolumeData v = read_ome_zarr(path);
    EXPECT_EQ(v.dims, glm::ivec3(7, 6, 5));
    EXPECT_EQ(v.type(), storage[n]);
    EXPECT_EQ(read_ome_zarr_header(path).type, storage[n]);
    expect_reference_voxels(v, dir / ("dt" + std::to_string(n) + ".f64"));
  }
}

TEST(OmeZarr, EveryCompressorReadsAsZarrDoes) {
  SKIP_WITHOUT_ZARR();
  TempDir dir;
  ASSERT_TRUE(test::run_zarr_python(dir, R"PY(
rng = np.random.default_rng(3)
data = (rng.integers(0, 40, (9, 10, 11)) * 100).astype('<u2')
codecs = [None, Zlib(level=6), GZip(level=5), Blosc(cname='lz4', shuffle=Blosc.SHUFFLE),
          Blosc(cname='zstd', clevel=3, shuffle=Blosc.BITSHUFFLE), Zstd(level=3)]
for n, c in enumerate(codecs):
    a = image(f'c{n}.zarr', [data], chunks=[(4, 4, 5)], compressor=c)
    ref(f'c{n}.f64', a[0][...])
)PY"));
  for (int n = 0; n < 6; ++n) {
    SCOPED_TRACE(n);
    expect_reference_voxels(read_ome_zarr(dir / ("c" + std::to_string(n) + ".zarr")),
                            dir / ("c" + std::to_string(n) + ".f64"));
  }
}

TEST(OmeZarr, SlashSeparatorAndMissingChunksHoldTheFillValue) {
  SKIP_WITHOUT_ZARR();
  TempDir dir;
  ASSERT_TRUE(test::run_zarr_python(dir, R"PY(
data = np.arange(6 * 7 * 8, dtype='<i2').reshape(6, 7, 8)
def part(a, d):
    a[:3, 2:5, :] = d[:3, 2:5, :]
a = image('slash.zarr', [data], chunks=[(2, 3, 3)], compressor=Zstd(), separator='/',
          fill_value=-7, write=part)
ref('slash.f64', a[0][...])
f = np.linspace(-1, 1, 6 * 7 * 8).astype('<f4').reshape(6, 7, 8)
a = image('nan.zarr', [f], chunks=[(4, 4, 4)], compressor=Blosc(cname='lz4'), fill_value=np.nan,
          write=part)
ref('nan.f64', a[0][...])
assert os.path.isdir('slash.zarr/0/0') and not os.path.exists('slash.zarr/0/2')
)PY"));
  const VolumeData slash = read_ome_zarr(dir / "slash.zarr");
  expect_reference_voxels(slash, dir / "slash.f64");
  EXPECT_EQ(slash.value_at(0, 0, 5), -7.0);
  const VolumeData nan = read_ome_zarr(dir / "nan.zarr");
  expect_reference_voxels(nan, dir / "nan.f64");
  EXPECT_TRUE(std::isnan(nan.value_at(0, 0, 5)));
}

TEST(OmeZarr, MultiscaleLevelsGiveSpacingAndOrigin) {
  SKIP_WITHOUT_ZARR();
  TempDir dir;
  ASSERT_TRUE(test::run_zarr_python(dir, R"PY(
d0 = np.arange(8 * 10 * 12, dtype='|u1').reshape(8, 10, 12)
d1 = np.ascontiguousarray(d0[::2, ::2, ::2])
a = image('ms.zarr', [d0, d1], chunks=[(3, 4, 5), (2, 2, 2)], compressor=GZip(),
          scales=[[0.5, 0.4, 0.3], [1.0, 0.8, 0.6]],
          translations=[[10.0, 20.0, 30.0], [10.25, 20.2, 30.15]], ms_scale=[2.0, 3.0, 4.0])
ref('l0.f64', a[0][...])
ref('l1.f64', a[1][...])
)PY"));
  const auto path = dir / "ms.zarr";
  // Dataset scale then translation, then the multiscale-level scale (which scales both).
  const VolumeData l0 = read_ome_zarr(path, 0);
  EXPECT_EQ(l0.dims, glm::ivec3(12, 10, 8));
  const glm::dvec3 s0(0.3 * 4, 0.4 * 3, 0.5 * 2), o0(30.0 * 4, 20.0 * 3, 10.0 * 2);
  const VolumeData l1 = read_ome_zarr(path, 1);
  EXPECT_EQ(l1.dims, glm::ivec3(6, 5, 4));
  const glm::dvec3 s1(0.6 * 4, 0.8 * 3, 1.0 * 2), o1(30.15 * 4, 20.2 * 3, 10.25 * 2);
  for (int a = 0; a < 3; ++a) {
    EXPECT_NEAR(l0.index_to_world[a][a], s0[a], 1e-12);
    EXPECT_NEAR(l0.index_to_world[3][a], o0[a], 1e-12);
    EXPECT_NEAR(l1.index_to_world[a][a], s1[a], 1e-12);
    EXPECT_NEAR(l1.index_to_world[3][a], o1[a], 1e-12);
    for (int b = 0; b < 3; ++b)
      if (a != b) {
        EXPECT_EQ(l0.index_to_world[a][b], 0.0);
      }
  }
  EXPECT_EQ(read_ome_zarr_header(path).index_to_world, l0.index_to_world);
  expect_reference_voxels(l0, dir / "l0.f64");
  expect_reference_voxels(l1, dir / "l1.f64");
  expect_error([&] { read_ome_zarr(path, 2); }, {"ms.zarr", "level 2", "0 to 1"});
  // Wired in as a volume format: by folder, with its frames.
  EXPECT_TRUE(is_volume_file(path));
  EXPECT_FALSE(is_dicom_source(path));
  EXPECT_EQ(read_volume(path).index_to_world, l0.index_to_world);
  EXPECT_EQ(read_volume_header(path).dims, l0.dims);
}

// Axis units become millimetres (microscopes write micrometres); an unknown unit is refused.
TEST(OmeZarr, SpaceUnitsBecomeMillimetres) {
  SKIP_WITHOUT_ZARR();
  TempDir dir;
  ASSERT_TRUE(test::run_zarr_python(dir, R"PY(
for name, units in [('um.zarr', {'z': 'micrometer', 'y': 'nanometer', 'x': 'millimeter'}),
                    ('pc.zarr', {'z': 'parsec', 'y': 'meter', 'x': 'meter'})]:
    image(name, [np.zeros((2, 3, 4), '|u1')], scales=[[2.0, 3.0, 4.0]],
          translations=[[5.0, 6.0, 7.0]])
    attrs = json.load(open(name + '/.zattrs'))
    for axis in attrs['multiscales'][0]['axes']:
        axis['unit'] = units[axis['name']]
    json.dump(attrs, open(name + '/.zattrs', 'w'))
)PY"));
  const VolumeData v = read_ome_zarr(dir / "um.zarr");
  const glm::dvec3 spacing(4.0, 3.0e-6, 2.0e-3), origin(7.0, 6.0e-6, 5.0e-3);  // x, y, z
  for (int a = 0; a < 3; ++a) {
    EXPECT_NEAR(v.index_to_world[a][a], spacing[a], 1e-15) << a;
    EXPECT_NEAR(v.index_to_world[3][a], origin[a], 1e-15) << a;
  }
  expect_error([&] { read_ome_zarr(dir / "pc.zarr"); }, {".zattrs", "'z'", "parsec"});
}

TEST(OmeZarr, FiveDimensionsPickFrameAndChannel) {
  SKIP_WITHOUT_ZARR();
  TempDir dir;
  ASSERT_TRUE(test::run_zarr_python(dir, R"PY(
data = np.random.default_rng(5).integers(0, 60000, (3, 2, 4, 5, 6)).astype('>u2')
a = image('tczyx.zarr', [data], axes='tczyx', chunks=[(2, 1, 3, 2, 4)], compressor=Blosc())
ref('t2c1.f64', a[0][2, 1])
ref('t0c0.f64', a[0][0, 0])
ref('t2c0.f64', a[0][2, 0])
d = np.arange(2 * 3 * 4 * 5, dtype='<f4').reshape(2, 3, 4, 5)
a = image('czyx.zarr', [d], axes='czyx', chunks=[(1, 2, 2, 2)])
ref('c1.f64', a[0][1])
)PY"));
  const auto path = dir / "tczyx.zarr";
  const VolumeHeader h = read_ome_zarr_header(path);
  EXPECT_EQ(h.frames, 3);
  EXPECT_EQ(h.dims, glm::ivec3(6, 5, 4));
  expect_reference_voxels(read_ome_zarr(path, 0, 2, 1), dir / "t2c1.f64");
  expect_reference_voxels(read_ome_zarr(path, 0, 0, 0), dir / "t0c0.f64");
  expect_reference_voxels(read_ome_zarr(dir / "czyx.zarr", 0, 0, 1), dir / "c1.f64");
  // read_volume's frame is the time point (channel 0).
  expect_reference_voxels(read_volume(path, 2), dir / "t2c0.f64");
  expect_error([&] { read_ome_zarr(path, 0, 3, 0); }, {"frame 3", "0 to 2"});
  expect_error([&] { read_ome_zarr(path, 0, 0, 2); }, {"channel 2", "0 to 1"});
}

// A good .zarray with one field replaced.
std::string zarray_with(const std::string& field, const std::string& value) {
  std::string text =
      R"({"zarr_format": 2, "shape": [4, 5, 6], "chunks": [2, 5, 6], "dtype": "<u2",
          "order": "C", "fill_value": 0, "compressor": {"id": "zlib", "level": 1},
          "filters": null, "dimension_separator": "."})";
  const size_t at = text.find("\"" + field + "\"");
  const size_t colon = text.find(':', at);
  size_t end = colon + 1;
  int depth = 0;
  for (; end < text.size(); ++end) {
    const char c = text[end];
    if (c == '{' || c == '[') ++depth;
    if (c == '}' || c == ']') {
      if (depth == 0) break;
      --depth;
    }
    if (c == ',' && depth == 0) break;
  }
  return text.substr(0, colon + 1) + " " + value + text.substr(end);
}

TEST(OmeZarr, BadMetadataIsRefusedByField) {
  const std::filesystem::path dir = "x.zarr/0";
  const auto parse = [&](const std::string& text) { return [=] { parse_zarray(text, dir, "A"); }; };
  EXPECT_NO_THROW(parse_zarray(zarray_with("order", "\"C\""), dir, "A"));
  EXPECT_EQ(parse_zarray(zarray_with("dimension_separator", "null"), dir, "A").separator, '.');
  expect_error(parse(zarray_with("order", "\"F\"")), {"A", "'order'", "Fortran"});
  expect_error(parse(zarray_with("compressor", R"({"id": "lzma"})")), {"'compressor'", "lzma"});
  expect_error(parse(zarray_with("filters", R"([{"id": "delta", "dtype": "<u2"}])")),
               {"'filters'", "delta"});
  expect_error(parse(zarray_with("shape", "[2147483647, 2147483647, 2147483647, 2147483647, 9]")),
               {"'shape'", "2^64"});
  expect_error(parse(zarray_with("shape", "[4, -5, 6]")), {"'shape'", ">= 1"});
  expect_error(parse(zarray_with("chunks", "[2, 5]")), {"'chunks'", "'shape' has 3"});
  expect_error(parse(zarray_with("chunks", "[2000, 2000, 2000]")), {"'chunks'", "elements"});
  expect_error(parse(zarray_with("dtype", "\"<f2\"")), {"'dtype'", "<f2"});
  expect_error(parse(zarray_with("dtype", "\"|u2\"")), {"'dtype'", "|u2"});
  expect_error(parse(zarray_with("fill_value", "70000")), {"'fill_value'", "70000"});
  expect_error(parse(zarray_with("dimension_separator", "\"-\"")), {"'dimension_separator'"});
  expect_error(parse(zarray_with("zarr_format", "3")), {"'zarr_format'", "v2"});
  expect_error(parse("{\"shape\": [4, 5"), {"A", "not JSON"});
}

TEST(OmeZarr, BadChunksAreRefusedNamingTheChunk) {
  SKIP_WITHOUT_ZARR();
  TempDir dir;
  ASSERT_TRUE(test::run_zarr_python(dir, R"PY(
data = np.arange(4 * 5 * 6, dtype='<u2').reshape(4, 5, 6)
codecs = {'zlib': Zlib(), 'gzip': GZip(), 'blosc': Blosc(), 'zstd': Zstd(), 'none': None}
for name, c in codecs.items():
    image(f'{name}.zarr', [data], chunks=[(2, 5, 6)], compressor=c)
    # A chunk bomb: a valid stream of ten times the chunk's bytes.
    image(f'{name}_bomb.zarr', [data], chunks=[(2, 5, 6)], compressor=c)
    big = np.zeros(10 * 2 * 5 * 6, dtype='<u2')
    with open(f'{name}_bomb.zarr/0/0.0.0', 'wb') as f:
        f.write(bytes(c.encode(big)) if c else big.tobytes())
image('short.zarr', [data], chunks=[(2, 5, 6)], compressor=Zlib())
with open('short.zarr/0/1.0.0', 'wb') as f:
    f.write(zlib.compress(np.zeros(10, dtype='<u2').tobytes()))
)PY"));
  for (const char* name : {"zlib", "gzip", "blosc", "zstd", "none"}) {
    SCOPED_TRACE(name);
    const auto good = dir / (std::string(name) + ".zarr");
    ASSERT_NO_THROW(read_ome_zarr(good));
    // Truncated: the chunk file's second half gone.
    const auto chunk = good / "0" / "1.0.0";
    const std::string bytes = test::read_bytes(chunk);
    test::write_bytes(chunk, bytes.substr(0, bytes.size() / 2));
    expect_error([&] { read_ome_zarr(good); }, {"1.0.0"});
    // Corrupt: bytes in the middle flipped (blosc and none may not notice: their data is raw).
    std::string flipped = bytes;
    for (size_t i = bytes.size() / 3; i < bytes.size() / 3 + 8; ++i) flipped[i] ^= 0x5a;
    test::write_bytes(chunk, flipped);
    if (std::string(name) != "none" && std::string(name) != "blosc")
      expect_error([&] { read_ome_zarr(good); }, {"1.0.0"});
    const auto bomb = dir / (std::string(name) + "_bomb.zarr");
    if (std::string(name) == "none")
      expect_error([&] { read_ome_zarr(bomb); }, {"0.0.0", "holds 1200 bytes, expected 120"});
    else
      expect_error([&] { read_ome_zarr(bomb); }, {"0.0.0", "chunk decompresses to", "120"});
  }
  expect_error([&] { read_ome_zarr(dir / "short.zarr"); }, {"1.0.0", "20 bytes, expected 120"});
}

TEST(OmeZarr, BadFoldersAreRefused) {
  TempDir dir;
  expect_error([&] { read_ome_zarr(dir / "none.zarr"); }, {"none.zarr", "no such file or folder"});
  dir.write("v3.zarr/zarr.json", "{}");
  expect_error([&] { read_ome_zarr(dir / "v3.zarr"); }, {"v3.zarr", "zarr_format", "not 3"});
  dir.write("plain.zarr/.zattrs", "{}");
  expect_error([&] { read_ome_zarr(dir / "plain.zarr"); }, {".zattrs", "multiscales"});
  dir.write("axes.zarr/.zattrs",
            R"({"multiscales": [{"axes": ["c", "y", "x"], "datasets": [{"path": "0"}]}]})");
  expect_error([&] { read_ome_zarr(dir / "axes.zarr"); }, {"axes", "c,y,x"});
  // Before NGFF 0.3 there were no axes: five dimensions, t, c, z, y, x.
  dir.write("old.zarr/.zattrs", R"({"multiscales": [{"datasets": [{"path": "0"}]}]})");
  dir.write("old.zarr/0/.zarray",
            R"({"zarr_format": 2, "shape": [1, 1, 2, 3, 4], "chunks": [1, 1, 2, 3, 4],
                "dtype": "|u1", "order": "C", "fill_value": 5, "compressor": null,
                "filters": null})");
  EXPECT_EQ(read_ome_zarr(dir / "old.zarr").value_at(3, 2, 1), 5.0);
  dir.write("old.zarr/0/.zarray",
            R"({"zarr_format": 2, "shape": [2, 3, 4], "chunks": [2, 3, 4], "dtype": "|u1",
                "order": "C", "fill_value": 5, "compressor": null, "filters": null})");
  expect_error([&] { read_ome_zarr(dir / "old.zarr"); }, {"3 dimensions", "axes names 5"});
  dir.write("bad.zarr/.zattrs",
            R"({"multiscales": [{"axes": ["z", "y", "x"], "datasets": [{"path": "0"}]}]})");
  dir.write("bad.zarr/0/.zarray", "not json");
  expect_error([&] { read_ome_zarr(dir / "bad.zarr"); }, {".zarray", "not JSON"});
  dir.write("big.zarr/.zattrs",
            R"({"multiscales": [{"axes": ["z", "y", "x"], "datasets": [{"path": "0"}]}]})");
  dir.write("big.zarr/0/.zarray",
            R"({"zarr_format": 2, "shape": [100000, 100000, 100000], "chunks": [8, 8, 8],
                "dtype": "|u1", "order": "C", "fill_value": 0, "compressor": null,
                "filters": null})");
  expect_error([&] { read_ome_zarr(dir / "big.zarr"); }, {".zarray", "'shape'"});
  dir.write("tiny.zarr/.zattrs",
            R"({"multiscales": [{"axes": ["z", "y", "x"], "datasets": [{"path": "0"}]}]})");
  dir.write("tiny.zarr/0/.zarray",
            R"({"zarr_format": 2, "shape": [200, 200, 200], "chunks": [1, 1, 1],
                "dtype": "|u1", "order": "C", "fill_value": 0, "compressor": null,
                "filters": null})");
  expect_error([&] { read_ome_zarr(dir / "tiny.zarr"); }, {".zarray", "'chunks'", "8000000"});
  EXPECT_TRUE(is_zarr_folder(dir / "big.zarr"));
  EXPECT_FALSE(is_zarr_folder(dir.path()));
}

// The fuzz target's seeds (metadata, a marker line, one stored file) decode: they reach the
// codecs, and the v3 ones the shard index.
TEST(OmeZarr, FuzzSeedsDecode) {
  const auto corpus =
      std::filesystem::path(IMX_EXAMPLES_DIR).parent_path() / "fuzz/corpus/fuzz_zarr";
  int seeds = 0, v3 = 0, shards = 0;
  for (const auto& entry : std::filesystem::directory_iterator(corpus)) {
    SCOPED_TRACE(entry.path().string());
    const std::string input = test::read_bytes(entry.path());
    const std::string marker = "\n@@DATA@@\n";
    const size_t at = input.find(marker);
    ASSERT_NE(at, std::string::npos);
    const std::string head = input.substr(0, at);
    const bool is_v3 = head.find("\"node_type\"") != std::string::npos;
    const ZarrArray a =
        is_v3 ? parse_zarr_json_array(head, "x", "seed") : parse_zarray(head, "x", "seed");
    const std::string stored = input.substr(at + marker.size());
    size_t chunks = 0;
    EXPECT_NO_THROW(
        chunks = decode_zarr_file(
            a, {reinterpret_cast<const uint8_t*>(stored.data()), stored.size()}, 8, "seed"));
    EXPECT_GE(chunks, 1u);
    ++seeds;
    v3 += is_v3;
    shards += a.shard.has_value();
  }
  EXPECT_GE(seeds, 7);
  EXPECT_GE(v3, 4);
  EXPECT_GE(shards, 2);
}

}  // namespace
}  // namespace imx::detail
