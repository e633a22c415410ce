// TIFF files that lie, are cut short, corrupt or unread kinds: each is refused by one imx::Error
// naming the file, page and field, before any allocation a lie would size, and never read as
// wrong voxels.
#include <filesystem>
#include <string>

#include <gtest/gtest.h>

#include "expect_error.hpp"
#include "intermix/io.hpp"
#include "intermix/limits.hpp"
#include "io/tiff/ome_xml.hpp"
#include "io/tiff/tiff_reader.hpp"
#include "temp_dir.hpp"
#include "tifffile_files.hpp"

namespace imx::detail {
namespace {

using test::expect_error;
using test::TempDir;

// A memory budget for one test, restored after it.
class Budget {
 public:
  explicit Budget(uint64_t bytes) : saved_(input_limits()) {
    set_input_limits({bytes, saved_.allow_external_data});
  }
  ~Budget() { set_input_limits(saved_); }

 private:
  InputLimits saved_;
};

TEST(TiffHostile, CutShortCorruptAndLyingStripsAreRefused) {
  SKIP_WITHOUT_TIFFFILE();
  TempDir dir;
  ASSERT_TRUE(test::run_tifffile_python(dir, R"PY(
data = np.arange(3 * 20 * 30, dtype='<u2').reshape(3, 20, 30)
for name, kw in [('raw', {}), ('zlib', dict(compression='zlib')),
                 ('tiled', dict(tile=(16, 16), compression='zlib'))]:
    tifffile.imwrite(name + '.tif', data, **kw)
    size = os.path.getsize(name + '.tif')
    with open(name + '.tif', 'rb') as f:
        whole = f.read()
    # Cut short: the last page's data gone (its IFD is written before it by tifffile? no: after).
    with open(name + '_cut.tif', 'wb') as f:
        f.write(whole[:size * 2 // 3])
    # Corrupt: the middle of the data flipped.
    with tifffile.TiffFile(name + '.tif') as t:
        key = 'TileOffsets' if 'tile' in kw else 'StripOffsets'
        at = t.pages[1].tags[key].value[0]
    flipped = bytearray(whole)
    for i in range(at + 2, at + 40):
        flipped[i] ^= 0x5A
    with open(name + '_flip.tif', 'wb') as f:
        f.write(flipped)
# Lying StripByteCounts: too few bytes for a strip's rows (libtiff would read on regardless); the
# same for a page's only strip (libtiff recomputes that count from the page's size, a note in
# --verbose); a gigabyte from near the end of the file.
tifffile.imwrite('lying.tif', data, rowsperstrip=5)
with tifffile.TiffFile('lying.tif') as t:
    counts = t.pages[1].tags['StripByteCounts']
    short = counts.dtype == 3
# The last strip: libtiff recomputes every count of an uncompressed page whose first two differ.
patch('lying.tif', counts.valueoffset + 3 * (2 if short else 4), '<H' if short else '<I', 100)
tifffile.imwrite('lying1.tif', data, rowsperstrip=20)
patch('lying1.tif', tag_value_at('lying1.tif', 1, 'StripByteCounts'), '<I', 100)
tifffile.imwrite('beyond.tif', data, rowsperstrip=20)
patch('beyond.tif', tag_value_at('beyond.tif', 1, 'StripOffsets'), '<I',
      os.path.getsize('beyond.tif') - 50)
patch('beyond.tif', tag_value_at('beyond.tif', 1, 'StripByteCounts'), '<I', 1 << 30)
# A compressed strip that decodes to fewer bytes than its rows: a short zlib stream.
import zlib
tifffile.imwrite('short.tif', data, rowsperstrip=20, compression='zlib')
with tifffile.TiffFile('short.tif') as t:
    off = t.pages[2].tags['StripOffsets'].value[0]
    count = t.pages[2].tags['StripByteCounts'].value[0]
small = zlib.compress(bytes(100))
assert len(small) <= count
patch('short.tif', off, f'{len(small)}s', small)
patch('short.tif', tag_value_at('short.tif', 2, 'StripByteCounts'), '<I', len(small))
)PY"));
  for (const char* name : {"raw", "zlib", "tiled"}) {
    SCOPED_TRACE(name);
    const auto good = dir / (std::string(name) + ".tif");
    ASSERT_NO_THROW(read_tiff(good));
    expect_error([&] { read_tiff(dir / (std::string(name) + "_cut.tif")); },
                 {std::string(name) + "_cut.tif"});
    if (std::string(name) != "raw")  // raw data has no check: flipped bytes are values
      expect_error([&] { read_tiff(dir / (std::string(name) + "_flip.tif")); },
                   {std::string(name) + "_flip.tif", "page 1"});
  }
  expect_error([&] { read_tiff(dir / "lying.tif"); },
               {"lying.tif", "page 1", "strip 3", "StripByteCounts gives 100 bytes", "300"});
  const VolumeData good = read_tiff(dir / "raw.tif"), repaired = read_tiff(dir / "lying1.tif");
  EXPECT_TRUE(repaired.voxels == good.voxels);
  expect_error([&] { read_tiff(dir / "beyond.tif"); }, {"beyond.tif", "page 1", "strip 0"});
  expect_error([&] { read_tiff(dir / "short.tif"); }, {"short.tif", "page 2", "strip 0"});
  // Pages before the bad one read in a region that does not reach it.
  EXPECT_NO_THROW(read_tiff_region(dir / "short.tif", {{0, 0, 0}, {30, 20, 2}}, 0));
}

TEST(TiffHostile, PagesThatDisagreeAreRefusedByPageAndField) {
  SKIP_WITHOUT_TIFFFILE();
  TempDir dir;
  ASSERT_TRUE(test::run_tifffile_python(dir, R"PY(
with tifffile.TiffWriter('size.tif') as w:
    w.write(np.zeros((8, 9), '<u2'))
    w.write(np.zeros((8, 9), '<u2'))
    w.write(np.zeros((8, 10), '<u2'))
with tifffile.TiffWriter('type.tif') as w:
    w.write(np.zeros((8, 9), '<u2'))
    w.write(np.zeros((8, 9), '<i2'))
tifffile.imwrite('rgb.tif', np.zeros((2, 8, 9, 3), '|u1'), photometric='rgb')
tifffile.imwrite('palette.tif', np.zeros((2, 8, 9), '|u1'), photometric='palette',
                 colormap=np.zeros((3, 256), '<u2'))
tifffile.imwrite('half.tif', np.zeros((2, 8, 9), '<f2'))
tifffile.imwrite('bits.tif', np.zeros((8, 9), bool))
tifffile.imwrite('white.tif', np.zeros((8, 9), '|u1'), photometric='miniswhite')
tifffile.imwrite('ome_size.ome.tif', np.zeros((2, 8, 9), '<u2'), metadata={'axes': 'ZYX'})
tifffile.imwrite('ome_z.ome.tif', np.zeros((2, 8, 9), '<u2'), metadata={'axes': 'ZYX'})
tifffile.imwrite('ij_pages.tif', np.zeros((4, 8, 9), '<u2'), imagej=True)
for name, old, new in [('ome_size.ome.tif', b'SizeX="9"', b'SizeX="7"'),
                       ('ome_z.ome.tif', b'SizeZ="2"', b'SizeZ="3"'),
                       ('ij_pages.tif', b'images=4', b'images=8')]:
    with open(name, 'rb') as f:
        b = f.read()
    assert old in b
    with open(name, 'wb') as f:
        f.write(b.replace(old, new))
)PY"));
  expect_error([&] { read_tiff(dir / "size.tif"); },
               {"size.tif", "page 2", "ImageWidth x ImageLength 10 x 8", "9 x 8"});
  expect_error([&] { read_tiff(dir / "type.tif"); }, {"type.tif", "page 1", "int16", "uint16"});
  expect_error([&] { read_tiff(dir / "rgb.tif"); }, {"rgb.tif", "page 0", "SamplesPerPixel 3"});
  expect_error([&] { read_tiff(dir / "palette.tif"); }, {"palette.tif", "page 0", "Palette"});
  expect_error([&] { read_tiff(dir / "half.tif"); }, {"half.tif", "BitsPerSample 16", "float"});
  expect_error([&] { read_tiff(dir / "bits.tif"); }, {"bits.tif", "BitsPerSample 1"});
  expect_error([&] { read_tiff(dir / "white.tif"); }, {"white.tif", "MinIsWhite"});
  expect_error([&] { read_tiff_header(dir / "ome_size.ome.tif"); },
               {"ome_size.ome.tif", "page 0", "9 x 8", "7 x 8"});
  expect_error([&] { read_tiff(dir / "ome_z.ome.tif"); }, {"ome_z.ome.tif", "no page", "z=2"});
  expect_error([&] { read_tiff(dir / "ij_pages.tif"); }, {"ij_pages.tif", "images=8", "4 pages"});
}

TEST(TiffHostile, BombsAreRefusedBeforeAllocating) {
  SKIP_WITHOUT_TIFFFILE();
  TempDir dir;
  ASSERT_TRUE(test::run_tifffile_python(dir, R"PY(
for name, (w, h) in [('bomb.tif', (30000, 30000)), ('huge.tif', (65535, 65535))]:
    tifffile.imwrite(name, np.zeros((2, 16, 16), '<u2'), compression='zlib', rowsperstrip=16)
    for page in range(2):
        with tifffile.TiffFile(name) as t:
            tags = t.pages[page].tags
            offs = [tags[k].valueoffset for k in ('ImageWidth', 'ImageLength', 'RowsPerStrip')]
            kinds = [tags[k].dtype for k in ('ImageWidth', 'ImageLength', 'RowsPerStrip')]
        for o, k, v in zip(offs, kinds, (w, h, h)):
            patch(name, o, '<H' if k == 3 else '<I', v)
# A tile claiming 2^30 pixels for a 16 x 16 page.
tifffile.imwrite('tile.tif', np.zeros((16, 16), '<u2'), tile=(16, 16))
with tifffile.TiffFile('tile.tif') as t:
    tags = t.pages[0].tags
    for k in ('TileWidth', 'TileLength'):
        patch('tile.tif', tags[k].valueoffset, '<H' if tags[k].dtype == 3 else '<I', 32768)
)PY"));
  const Budget budget(uint64_t{256} << 20);
  // 2 x 30000^2 voxels of uint16: 3.6 GB from a file of a few hundred bytes.
  expect_error([&] { read_tiff(dir / "bomb.tif"); }, {"bomb.tif", "memory budget"});
  // Past 2^31 voxels a grid is only read by region (a render in bricks).
  expect_error([&] { read_tiff(dir / "huge.tif"); },
               {"huge.tif", "65535x65535x2 voxels", "one volume holds in memory"});
  expect_error([&] { read_tiff(dir / "tile.tif"); }, {"tile.tif", "page 0", "TileWidth"});
}

TEST(TiffHostile, NotTiffAndBadOmeXmlAreRefused) {
  TempDir dir;
  dir.write("empty.tif", "");
  expect_error([&] { read_tiff(dir / "empty.tif"); }, {"empty.tif", "not a readable TIFF"});
  dir.write("text.tif", "II*\0 this is not a TIFF at all");
  expect_error([&] { read_tiff(dir / "text.tif"); }, {"text.tif"});
  const std::string what = "x.ome.tif";
  const auto parse = [&](const std::string& xml) { return [=] { parse_ome_xml(xml, what); }; };
  const std::string pixels =
      R"(<OME><Image><Pixels DimensionOrder="XYZCT" Type="uint16" SizeX="4" SizeY="3" )";
  EXPECT_EQ(parse_ome_xml(pixels + R"(SizeZ="2"/></Image></OME>)", what).size_z, 2);
  expect_error(parse(pixels + R"(SizeZ="-2"/></Image></OME>)"), {what, "'SizeZ'", "-2"});
  expect_error(parse(pixels + R"(SizeZ="2" PhysicalSizeX="0"/></Image></OME>)"),
               {"'PhysicalSizeX'", "positive"});
  expect_error(parse(R"(<OME><Image><Pixels DimensionOrder="XYZ" SizeX="4" SizeY="3"/></Image>)"
                     R"(</OME>)"),
               {"'DimensionOrder'", "XYZ"});
  expect_error(parse("<OME><Image>"), {what, "malformed"});
  expect_error(parse("<OME></OME>"), {what, "no Image"});
  expect_error(parse(R"(<!DOCTYPE OME [<!ENTITY a "aaaa">]><OME>&a;</OME>)"),
               {what, "document type"});
  expect_error(parse(std::string(kMaxOmeXmlBytes + 1, ' ')), {what, "bytes of OME-XML"});
}

// The fuzz target's seeds read: they reach the strips, tiles and descriptions.
TEST(TiffHostile, FuzzSeedsRead) {
  const auto corpus =
      std::filesystem::path(IMX_EXAMPLES_DIR).parent_path() / "fuzz/corpus/fuzz_tiff";
  int seeds = 0;
  for (const auto& entry : std::filesystem::directory_iterator(corpus)) {
    SCOPED_TRACE(entry.path().string());
    TempDir dir;
    const auto file = dir.write("in.tif", test::read_bytes(entry.path()));
    EXPECT_NO_THROW(read_volume(file));
    ++seeds;
  }
  EXPECT_GE(seeds, 4);
}

}  // namespace
}  // namespace imx::detail
