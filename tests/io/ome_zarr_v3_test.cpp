// OME-Zarr 0.5 (Zarr v3) volumes against fixtures written to the v3 specification: every codec,
// key encoding and shard layout, compared voxel by voxel with the arrays the script wrote.
#include <cmath>
#include <string>

#include <fmt/format.h>
#include <gtest/gtest.h>

#include "expect_error.hpp"
#include "intermix/io.hpp"
#include "io/zarr/crc32c.hpp"
#include "io/zarr/ome_zarr_reader.hpp"
#include "io/zarr/zarr_array.hpp"
#include "ome_zarr_v3_files.hpp"
#include "reference_voxels.hpp"
#include "temp_dir.hpp"

namespace imx::detail {
namespace {

using test::expect_error;
using test::TempDir;

// "c3.zarr": fmt, as GCC 12 warns (-Wrestrict) on a literal + std::string chain.
std::string numbered(const char* stem, int n, const char* ext) {
  return fmt::format("{}{}{}", stem, n, ext);
}

void expect_voxels(const VolumeData& v, const std::filesystem::path& ref_file) {
  test::expect_reference_voxels(v, ref_file, "the writer");
}

TEST(OmeZarrV3, Crc32cHasItsCheckValue) {
  const std::string text = "123456789";
  EXPECT_EQ(crc32c({reinterpret_cast<const uint8_t*>(text.data()), text.size()}), 0xE3069283u);
}

TEST(OmeZarrV3, EveryTypeCodecAndKeyEncodingReadsAsWritten) {
  SKIP_WITHOUT_ZARR();
  TempDir dir;
  ASSERT_TRUE(test::run_zarr3_python(dir, R"PY(
rng = np.random.default_rng(11)
le, be = codec('bytes', endian='little'), codec('bytes', endian='big')
chains = [
    [le],
    [be, codec('gzip', level=5)],
    [le, codec('zstd', level=3, checksum=False)],
    [le, codec('blosc', cname='lz4', clevel=5, shuffle='shuffle', typesize=2, blocksize=0)],
    [be, codec('blosc', cname='zstd', clevel=3, shuffle='bitshuffle', typesize=2, blocksize=0)],
    [le, codec('crc32c')],
    [codec('transpose', order=[2, 0, 1]), le, codec('gzip', level=1), codec('crc32c')],
    [codec('transpose', order=[1, 2, 0]), be, codec('crc32c'), codec('zstd', level=1)],
]
keys = [('default', None), ('default', '.'), ('v2', None), ('v2', '/')]
data = (rng.integers(0, 4000, (7, 9, 10))).astype('<u2')
for n, chain in enumerate(chains):
    key, sep = keys[n % 4]
    a = image3(f'c{n}.zarr', [data], chunks=[(3, 4, 6)], codecs=chain, key=key, separator=sep)
    ref(f'c{n}.f64', a[0])
types = ['u1', 'i1', 'i2', 'u2', 'i4', 'u4', 'i8', 'u8', 'f4', 'f8']
for n, t in enumerate(types):
    d = np.dtype(t)
    if d.kind == 'f':
        x = rng.normal(0, 100, (4, 5, 6)).astype(d)
    else:
        info = np.iinfo(d)
        x = rng.integers(max(info.min, -2**40), min(info.max, 2**40), (4, 5, 6), endpoint=True).astype(d)
    a = image3(f't{n}.zarr', [x], chunks=[(3, 3, 4)],
               codecs=[be if n % 2 else le, codec('gzip', level=1)])
    ref(f't{n}.f64', a[0])
)PY"));
  for (int n = 0; n < 8; ++n) {
    SCOPED_TRACE(n);
    const auto path = dir / numbered("c", n, ".zarr");
    const VolumeData v = read_ome_zarr(path);
    EXPECT_EQ(v.dims, glm::ivec3(10, 9, 7));
    expect_voxels(v, dir / numbered("c", n, ".f64"));
  }
  const VoxelType storage[] = {VoxelType::u8,  VoxelType::i16, VoxelType::i16, VoxelType::u16,
                               VoxelType::f32, VoxelType::f32, VoxelType::f32, VoxelType::f32,
                               VoxelType::f32, VoxelType::f32};
  for (int n = 0; n < 10; ++n) {
    SCOPED_TRACE(n);
    const auto path = dir / numbered("t", n, ".zarr");
    const VolumeData v = read_ome_zarr(path);
    EXPECT_EQ(v.type(), storage[n]);
    EXPECT_EQ(read_ome_zarr_header(path).type, storage[n]);
    expect_voxels(v, dir / numbered("t", n, ".f64"));
  }
  // Wired in as a volume format, by folder.
  EXPECT_TRUE(is_volume_file(dir / "c0.zarr"));
  expect_voxels(read_volume(dir / "c1.zarr"), dir / "c1.f64");
}

TEST(OmeZarrV3, MissingChunksAndHexFillValues) {
  SKIP_WITHOUT_ZARR();
  TempDir dir;
  ASSERT_TRUE(test::run_zarr3_python(dir, R"PY(
data = np.arange(6 * 7 * 8, dtype='<i2').reshape(6, 7, 8)
a = image3('int.zarr', [data], chunks=[(2, 3, 3)], fill_value=-7,
           codecs=[codec('bytes', endian='little'), codec('zstd', level=1)],
           keep=lambda p: p[0] != 2)
ref('int.f64', a[0])
f = np.linspace(-1, 1, 6 * 7 * 8).astype('<f4').reshape(6, 7, 8)
for n, fill in enumerate([float('nan'), '0x3fc00000', '0xff800000']):
    a = image3(f'f{n}.zarr', [f], chunks=[(4, 4, 4)], fill_value=fill,
               keep=lambda p: p[0] == 0)
    ref(f'f{n}.f64', a[0])
assert not os.path.exists('int.zarr/0/c/2')
)PY"));
  const VolumeData v = read_ome_zarr(dir / "int.zarr");
  expect_voxels(v, dir / "int.f64");
  EXPECT_EQ(v.value_at(0, 0, 5), -7.0);
  for (int n = 0; n < 3; ++n)
    expect_voxels(read_ome_zarr(dir / numbered("f", n, ".zarr")), dir / numbered("f", n, ".f64"));
  EXPECT_TRUE(std::isnan(read_ome_zarr(dir / "f0.zarr").value_at(0, 0, 5)));
  EXPECT_EQ(read_ome_zarr(dir / "f1.zarr").value_at(0, 0, 5), 1.5);
  EXPECT_EQ(read_ome_zarr(dir / "f2.zarr").value_at(0, 0, 5), -INFINITY);
}

TEST(OmeZarrV3, ShardsWithMissingInnerChunksReadAsWritten) {
  SKIP_WITHOUT_ZARR();
  TempDir dir;
  ASSERT_TRUE(test::run_zarr3_python(dir, R"PY(
rng = np.random.default_rng(4)
data = rng.integers(1, 60000, (10, 13, 17)).astype('<u2')
data[:4, :6, :] = 0        # whole inner chunks of the fill value: left out of their shard
data[8:, 6:, 8:] = 0
index_codecs = [codec('bytes', endian='little'), codec('crc32c')]
inner = [[codec('bytes', endian='little'), codec('gzip', level=1)],
         [codec('transpose', order=[2, 1, 0]), codec('bytes', endian='big'),
          codec('blosc', cname='lz4', clevel=5, shuffle='shuffle', typesize=2, blocksize=0)],
         [codec('bytes', endian='little')]]
for n, location in enumerate(['end', 'start', 'end']):
    shard = codec('sharding_indexed', chunk_shape=[2, 3, 4], codecs=inner[n],
                  index_codecs=index_codecs if n < 2 else [codec('bytes', endian='big')],
                  index_location=location)
    a = image3(f's{n}.zarr', [data], chunks=[(4, 6, 8)], codecs=[shard],
               keep=lambda p: p != (0, 0, 1))   # one whole shard missing too
    ref(f's{n}.f64', a[0])
# Channels and time in shards: one channel is read through the others' inner chunks.
d5 = rng.integers(0, 255, (2, 3, 5, 6, 7)).astype('|u1')
shard = codec('sharding_indexed', chunk_shape=[1, 1, 2, 3, 4],
              codecs=[codec('bytes'), codec('zstd', level=1)],
              index_codecs=index_codecs)
a = image3('tczyx.zarr', [d5], axes='tczyx', chunks=[(2, 3, 4, 6, 8)], codecs=[shard])
ref('t1c2.f64', a[0][1, 2])
)PY"));
  for (int n = 0; n < 3; ++n) {
    SCOPED_TRACE(n);
    expect_voxels(read_ome_zarr(dir / numbered("s", n, ".zarr")), dir / numbered("s", n, ".f64"));
  }
  expect_voxels(read_ome_zarr(dir / "tczyx.zarr", 0, 1, 2), dir / "t1c2.f64");
  const ZarrArray a = read_zarr_array(dir / "s0.zarr" / "0");
  ASSERT_TRUE(a.shard.has_value());
  EXPECT_EQ(a.shard->inner_chunks, 8u);
  EXPECT_EQ(a.chunks, (std::vector<int64_t>{2, 3, 4}));
}

TEST(OmeZarrV3, CorruptChunksAndShardsAreRefusedByName) {
  SKIP_WITHOUT_ZARR();
  TempDir dir;
  ASSERT_TRUE(test::run_zarr3_python(dir, R"PY(
data = np.arange(4 * 5 * 6, dtype='<u2').reshape(4, 5, 6) + 1
image3('crc.zarr', [data], chunks=[(2, 5, 6)],
       codecs=[codec('bytes', endian='little'), codec('gzip', level=1), codec('crc32c')])
shard = codec('sharding_indexed', chunk_shape=[2, 5, 3],
              codecs=[codec('bytes', endian='little')],
              index_codecs=[codec('bytes', endian='little'), codec('crc32c')])
image3('shard.zarr', [data], chunks=[(4, 5, 6)], codecs=[shard])
image3('plain.zarr', [data], chunks=[(4, 5, 6)],
       codecs=[codec('sharding_indexed', chunk_shape=[2, 5, 3], codecs=[codec('bytes', endian='little')],
                     index_codecs=[codec('bytes', endian='little')])])
)PY"));
  // A byte of a chunk flipped: its checksum no longer matches.
  const auto chunk = dir / "crc.zarr" / "0" / "c" / "1" / "0" / "0";
  std::string bytes = test::read_bytes(chunk);
  bytes[bytes.size() / 2] ^= 0x20;
  test::write_bytes(chunk, bytes);
  expect_error([&] { read_ome_zarr(dir / "crc.zarr"); }, {"c/1/0/0", "crc32c", "mismatch"});
  // The shard's index (at its end) with a byte flipped: refused before any inner chunk is read.
  const auto shard = dir / "shard.zarr" / "0" / "c" / "0" / "0" / "0";
  const std::string good = test::read_bytes(shard);
  bytes = good;
  bytes[bytes.size() - 10] ^= 0x01;
  test::write_bytes(shard, bytes);
  expect_error([&] { read_ome_zarr(dir / "shard.zarr"); }, {"c/0/0/0", "index", "crc32c"});
  // Shorter than its index.
  test::write_bytes(shard, good.substr(0, 20));
  expect_error([&] { read_ome_zarr(dir / "shard.zarr"); }, {"c/0/0/0", "shorter than its"});
  // An index entry claiming 2^62 bytes at offset 0 (no checksum to catch it): refused before
  // anything that size is allocated.
  const auto plain = dir / "plain.zarr" / "0" / "c" / "0" / "0" / "0";
  bytes = test::read_bytes(plain);
  const size_t entry = bytes.size() - 4 * 16 + 8;  // the first entry's nbytes
  for (int b = 0; b < 8; ++b) bytes[entry + static_cast<size_t>(b)] = b == 7 ? 0x40 : 0;
  test::write_bytes(plain, bytes);
  expect_error([&] { read_ome_zarr(dir / "plain.zarr"); }, {"c/0/0/0", "entry 0", "more than"});
  // An entry pointing past the file's end.
  bytes = test::read_bytes(plain);
  for (int b = 0; b < 8; ++b) bytes[entry + static_cast<size_t>(b)] = b == 0 ? 8 : 0;
  for (int b = 0; b < 8; ++b) bytes[entry - 8 + static_cast<size_t>(b)] = b == 1 ? 0x10 : 0;
  test::write_bytes(plain, bytes);
  expect_error([&] { read_ome_zarr(dir / "plain.zarr"); }, {"c/0/0/0", "outside the shard"});
}

// A good v3 array's zarr.json with one field replaced (or added).
std::string zarr_json_with(const std::string& field, const std::string& value) {
  nlohmann::json doc = nlohmann::json::parse(R"({
    "zarr_format": 3, "node_type": "array", "shape": [4, 5, 6], "data_type": "uint16",
    "chunk_grid": {"name": "regular", "configuration": {"chunk_shape": [2, 5, 6]}},
    "chunk_key_encoding": {"name": "default", "configuration": {"separator": "/"}},
    "fill_value": 0, "codecs": [{"name": "bytes", "configuration": {"endian": "little"}}],
    "attributes": {}, "dimension_names": ["z", "y", "x"]})");
  doc[field] = nlohmann::json::parse(value);
  return doc.dump();
}

TEST(OmeZarrV3, BadMetadataIsRefusedByField) {
  const std::filesystem::path dir = "x.zarr/0";
  const auto parse = [&](const std::string& text) {
    return [=] { parse_zarr_json_array(text, dir, "A"); };
  };
  const ZarrArray good = parse_zarr_json_array(zarr_json_with("attributes", "{}"), dir, "A");
  EXPECT_EQ(good.chunk_file(std::vector<int64_t>{1, 0, 2}), dir / "c/1/0/2");
  EXPECT_EQ(good.zarr_format, 3);
  expect_error(parse(zarr_json_with("data_type", "\"bool\"")), {"A", "'data_type'", "bool"});
  expect_error(parse(zarr_json_with("data_type", "\"float16\"")), {"'data_type'", "float16"});
  expect_error(parse(zarr_json_with("storage_transformers", R"([{"name": "x"}])")),
               {"'storage_transformers'"});
  EXPECT_NO_THROW(parse_zarr_json_array(zarr_json_with("storage_transformers", "[]"), dir, "A"));
  expect_error(parse(zarr_json_with("codecs", R"([{"name": "bytes", "configuration": {"endian":
      "little"}}, {"name": "lzma"}])")),
               {"'codecs'", "lzma", "not supported"});
  expect_error(parse(zarr_json_with("codecs", R"(["bytes"])")), {"'codecs'", "endian"});
  expect_error(parse(zarr_json_with("codecs", R"([{"name": "gzip"}])")), {"'codecs'", "before"});
  expect_error(parse(zarr_json_with("codecs", R"([{"name": "transpose", "configuration":
      {"order": [0, 0, 1]}}, "bytes"])")),
               {"transpose", "order"});
  expect_error(parse(zarr_json_with("chunk_grid", R"({"name": "rectilinear"})")),
               {"'chunk_grid'", "regular"});
  expect_error(parse(zarr_json_with("chunk_key_encoding", R"({"name": "other"})")),
               {"'chunk_key_encoding'"});
  // Extensions: ignored only when they say they need not be understood.
  EXPECT_NO_THROW(parse_zarr_json_array(
      zarr_json_with("my_extension", R"({"must_understand": false, "x": 1})"), dir, "A"));
  expect_error(parse(zarr_json_with("my_extension", R"({"must_understand": true})")),
               {"'my_extension'", "must be understood"});
  expect_error(parse(zarr_json_with("zarr_format", "2")), {"'zarr_format'", "not 3"});
  expect_error(parse(zarr_json_with("node_type", "\"group\"")), {"'node_type'"});
  expect_error(parse(zarr_json_with("fill_value", "\"0x12\"")), {"'fill_value'"});
  expect_error(parse(zarr_json_with("dimension_names", R"(["z", "y"])")), {"'dimension_names'"});
  // A lying shape: more elements than 2^64, and chunks beyond the voxel limit.
  expect_error(parse(zarr_json_with("shape", "[2147483647, 2147483647, 2147483647, 9]")),
               {"'shape'", "2^64"});
  expect_error(parse(zarr_json_with(
                   "chunk_grid",
                   R"({"name": "regular", "configuration": {"chunk_shape": [2000, 2000, 2000]}})")),
               {"'chunk_grid'", "elements"});
  // Shards: the inner shape must divide the shard's, and the index must have a fixed size.
  const auto sharded = [](const std::string& inner, const std::string& index) {
    return zarr_json_with(
        "codecs", R"([{"name": "sharding_indexed", "configuration": {"chunk_shape": )" + inner +
                      R"(, "codecs": [{"name": "bytes", "configuration": {"endian": "little"}}],
            "index_codecs": )" +
                      index + "}}]");
  };
  const std::string index = R"([{"name": "bytes", "configuration": {"endian": "little"}}])";
  EXPECT_NO_THROW(parse_zarr_json_array(sharded("[1, 5, 3]", index), dir, "A"));
  expect_error(parse(sharded("[2, 2, 3]", index)), {"chunk_shape", "does not divide"});
  // A shard of 2^30 inner chunks: its index (16 GiB) is refused before it is sized.
  nlohmann::json huge = nlohmann::json::parse(sharded("[1, 1, 1]", index));
  huge["chunk_grid"]["configuration"]["chunk_shape"] = {1024, 1024, 1024};
  expect_error(parse(huge.dump()), {"chunk_shape", "more than 1048576 inner chunks"});
  expect_error(parse(sharded("[1, 5, 3]", R"([{"name": "bytes", "configuration": {"endian":
      "little"}}, {"name": "gzip"}])")),
               {"index_codecs", "fixed size"});
}

TEST(OmeZarrV3, BadImagesAreRefusedByName) {
  SKIP_WITHOUT_ZARR();
  TempDir dir;
  ASSERT_TRUE(test::run_zarr3_python(dir, R"PY(
data = np.zeros((3, 4, 5), '|u1')
image3('names.zarr', [data])
meta = json.load(open('names.zarr/0/zarr.json'))
meta['dimension_names'] = ['x', 'y', 'z']
json.dump(meta, open('names.zarr/0/zarr.json', 'w'))
# A lying shape: a grid far beyond the voxel limit, in tiny chunks.
image3('huge.zarr', [data])
meta = json.load(open('huge.zarr/0/zarr.json'))
meta['shape'] = [100000, 100000, 100000]
json.dump(meta, open('huge.zarr/0/zarr.json', 'w'))
os.makedirs('array.zarr', exist_ok=True)
json.dump({'zarr_format': 3, 'node_type': 'array'}, open('array.zarr/zarr.json', 'w'))
os.makedirs('noome.zarr', exist_ok=True)
json.dump({'zarr_format': 3, 'node_type': 'group', 'attributes': {}}, open('noome.zarr/zarr.json', 'w'))
)PY"));
  expect_error([&] { read_ome_zarr(dir / "names.zarr"); }, {"dimension_names", "'x'", "'z'"});
  expect_error([&] { read_ome_zarr(dir / "huge.zarr"); }, {"zarr.json", "'shape'"});
  expect_error([&] { read_ome_zarr(dir / "array.zarr"); }, {"node_type", "group"});
  expect_error([&] { read_ome_zarr(dir / "noome.zarr"); }, {"attributes.ome"});
}

TEST(OmeZarrV3, OmeroChannelsGiveColourWindowAndLabel) {
  SKIP_WITHOUT_ZARR();
  TempDir dir;
  ASSERT_TRUE(test::run_zarr3_python(dir, R"PY(
d = np.zeros((3, 2, 3, 4), '<u2')
omero = {'channels': [
    {'label': 'DAPI', 'color': '0000FF', 'active': True,
     'window': {'start': 100, 'end': 900, 'min': 0, 'max': 4095}},
    {'label': 'GFP', 'color': '00ff00', 'active': False, 'window': {'start': 50, 'end': 60}},
    {'color': 'FF8000'}]}
image3('ch.zarr', [d], axes='czyx', omero=omero)
image3('bad.zarr', [d], axes='czyx', omero={'channels': [{'color': 'red'}]})
image3('one.zarr', [d[0]], omero={'channels': [{'label': 'only'}, {'label': 'extra'}]})
)PY"));
  const std::vector<OmeChannel> ch = read_ome_zarr_channels(dir / "ch.zarr");
  ASSERT_EQ(ch.size(), 3u);
  EXPECT_EQ(ch[0].label, "DAPI");
  EXPECT_EQ(ch[0].srgb, glm::vec3(0, 0, 1));
  ASSERT_TRUE(ch[0].window && ch[0].range);
  EXPECT_EQ(*ch[0].window, glm::dvec2(100, 900));
  EXPECT_EQ(*ch[0].range, glm::dvec2(0, 4095));
  EXPECT_FALSE(ch[1].active);
  EXPECT_EQ(ch[2].label, "channel 2");
  EXPECT_NEAR(ch[2].srgb.g, 128.0f / 255.0f, 1e-6f);
  EXPECT_FALSE(ch[2].window.has_value());
  // No channel axis: one channel; entries past it describe nothing and are left unread.
  const std::vector<OmeChannel> one = read_ome_zarr_channels(dir / "one.zarr");
  ASSERT_EQ(one.size(), 1u);
  EXPECT_EQ(one[0].label, "only");
  expect_error([&] { read_ome_zarr_channels(dir / "bad.zarr"); },
               {"zarr.json", "omero.channels[0].color", "red"});
}

}  // namespace
}  // namespace imx::detail
