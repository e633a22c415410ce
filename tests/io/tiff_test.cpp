// TIFF stacks, BigTIFF, ImageJ hyperstacks and OME-TIFF against tifffile's own reading of the
// same files (tests/support/tifffile_files.hpp); hostile files are in tiff_hostile_test.cpp.
#include <algorithm>
#include <cfloat>
#include <cmath>
#include <string>

#include <fmt/format.h>
#include <gtest/gtest.h>

#include "expect_error.hpp"
#include "intermix/dicom.hpp"
#include "intermix/io.hpp"
#include "io/registry/tiff_sniff.hpp"
#include "io/tiff/tiff_layout.hpp"
#include "io/tiff/tiff_reader.hpp"
#include "reference_voxels.hpp"
#include "temp_dir.hpp"
#include "tifffile_files.hpp"

namespace imx::detail {
namespace {

using test::expect_error;
using test::TempDir;

void expect_reference_voxels(const VolumeData& v, const std::filesystem::path& ref_file) {
  test::expect_reference_voxels(v, ref_file, "tifffile");
}

void expect_spacing(const VolumeData& v, glm::dvec3 mm) {
  for (int a = 0; a < 3; ++a) {
    EXPECT_NEAR(v.index_to_world[a][a], mm[a], 1e-12 * mm[a]) << "axis " << a;
    EXPECT_EQ(v.index_to_world[3][a], 0.0);
  }
}

TEST(Tiff, EveryDtypeReadsAsTifffileDoes) {
  SKIP_WITHOUT_TIFFFILE();
  TempDir dir;
  ASSERT_TRUE(test::run_tifffile_python(dir, R"PY(
rng = np.random.default_rng(7)
for n, dt in enumerate(['|u1', '|i1', '<u2', '<i2', '>u2', '>i2', '<u4', '>i4', '<f4', '>f4',
                        '<f8', '>f8', '<i8', '>u8']):
    info = np.iinfo(dt) if dt[1] in 'iu' else None
    if info is None:
        data = rng.normal(0, 1000, (5, 6, 7)).astype(dt)
        data[0, 0, :3] = [np.nan, np.inf if dt[2] == '4' else -1e300, -0.0]
    else:
        lo, hi = max(info.min, -2**40), min(info.max, 2**40)
        data = rng.integers(lo, hi, (5, 6, 7), endpoint=True).astype(dt)
    tifffile.imwrite(f'dt{n}.tif', data, byteorder='>' if dt[0] == '>' else '<',
                     compression='zlib' if n % 2 else None)
    ref(f'dt{n}.f64', tifffile.imread(f'dt{n}.tif'))
)PY"));
  const VoxelType storage[] = {VoxelType::u8,  VoxelType::i16, VoxelType::u16, VoxelType::i16,
                               VoxelType::u16, VoxelType::i16, VoxelType::f32, VoxelType::f32,
                               VoxelType::f32, VoxelType::f32, VoxelType::f32, VoxelType::f32,
                               VoxelType::f32, VoxelType::f32};
  for (int n = 0; n < 14; ++n) {
    SCOPED_TRACE(n);
    const auto path = dir / ("dt" + std::to_string(n) + ".tif");
    const VolumeData v = read_tiff(path);
    EXPECT_EQ(v.dims, glm::ivec3(7, 6, 5));
    EXPECT_EQ(v.type(), storage[n]);
    EXPECT_EQ(read_tiff_header(path).type, storage[n]);
    expect_reference_voxels(v, dir / ("dt" + std::to_string(n) + ".f64"));
  }
}

TEST(Tiff, CompressionsStripsTilesAndBigTiff) {
  SKIP_WITHOUT_TIFFFILE();
  TempDir dir;
  ASSERT_TRUE(test::run_tifffile_python(dir, R"PY(
rng = np.random.default_rng(3)
data = (rng.integers(0, 40, (4, 37, 45)) * 1000).astype('<u2')
cases = [dict(), dict(compression='zlib'), dict(compression='zlib', predictor=True),
         dict(compression='lzma'), dict(rowsperstrip=5), dict(rowsperstrip=6, compression='zlib'),
         dict(tile=(16, 16)), dict(tile=(32, 16), compression='zlib'),
         dict(bigtiff=True, tile=(16, 32)), dict(bigtiff=True, byteorder='>', compression='zlib'),
         dict(bigtiff=True, byteorder='>', tile=(16, 16), predictor=True, compression='zlib')]
for n, kw in enumerate(cases):
    tifffile.imwrite(f'c{n}.tif', data, **kw)
    ref(f'c{n}.f64', tifffile.imread(f'c{n}.tif'))
# LZW and PackBits through Pillow (tifffile needs imagecodecs to encode them); the reference is
# the array written, which tifffile reads back where it can decode.
for n, (comp, dt) in enumerate([('tiff_lzw', '<u2'), ('tiff_lzw', '|u1'), ('packbits', '<u2'),
                                 ('packbits', '|u1'), ('tiff_adobe_deflate', '<u2')]):
    a = data.astype(dt) if dt == '<u2' else (data // 1000).astype(dt)
    pil_stack(f'p{n}.tif', a, comp)
    if comp != 'tiff_lzw':
        assert (tifffile.imread(f'p{n}.tif') == a).all()
    ref(f'p{n}.f64', a)
with tifffile.TiffFile('c9.tif') as t:
    assert t.is_bigtiff and t.byteorder == '>'
)PY"));
  for (int n = 0; n < 11; ++n) {
    SCOPED_TRACE(n);
    const auto path = dir / ("c" + std::to_string(n) + ".tif");
    const VolumeData v = read_tiff(path);
    EXPECT_EQ(v.dims, glm::ivec3(45, 37, 4));
    expect_reference_voxels(v, dir / ("c" + std::to_string(n) + ".f64"));
    // Only the box's pages and rows: the same voxels as the whole read's.
    const VoxelBox box{{3, 5, 1}, {41, 30, 3}};
    const VolumeData part = read_tiff_region(path, box, 0);
    ASSERT_EQ(part.dims, box.size());
    for (int k = 0; k < box.size().z; ++k)
      for (int j = 0; j < box.size().y; ++j)
        for (int i = 0; i < box.size().x; ++i)
          ASSERT_EQ(part.value_at(i, j, k), v.value_at(i + 3, j + 5, k + 1)) << i << "," << j;
    EXPECT_EQ(part.index_to_world[3], v.index_to_world * glm::dvec4(3, 5, 1, 1));
  }
  for (int n = 0; n < 5; ++n) {
    SCOPED_TRACE("pillow " + std::to_string(n));
    expect_reference_voxels(read_volume(dir / ("p" + std::to_string(n) + ".tif")),
                            dir / ("p" + std::to_string(n) + ".f64"));
  }
}

TEST(Tiff, OmeTiffMapsPlanesByDimensionOrder) {
  SKIP_WITHOUT_TIFFFILE();
  TempDir dir;
  ASSERT_TRUE(test::run_tifffile_python(dir, R"PY(
rng = np.random.default_rng(5)
data = rng.integers(0, 60000, (2, 2, 3, 6, 7)).astype('<u2')   # t, c, z, y, x
# tifffile writes axes TCZYX as DimensionOrder XYZCT, and TZCYX as XYCZT.
tifffile.imwrite('zct.ome.tif', data, metadata={'axes': 'TCZYX', 'PhysicalSizeX': 5000,
                 'PhysicalSizeXUnit': 'nm', 'PhysicalSizeY': 0.25, 'PhysicalSizeZ': 2.0})
tifffile.imwrite('czt.ome.tif', np.ascontiguousarray(data.transpose(0, 2, 1, 3, 4)),
                 metadata={'axes': 'TZCYX', 'PhysicalSizeZ': 3.0, 'PhysicalSizeZUnit': 'mm'},
                 bigtiff=True, tile=(16, 16), compression='zlib')
for name in ['zct', 'czt']:
    with tifffile.TiffFile(name + '.ome.tif') as t:
        order = 'XYZCT' if name == 'zct' else 'XYCZT'
        assert f'DimensionOrder="{order}"' in t.pages[0].description
        s = t.series[0].asarray()
        s = s if name == 'zct' else s.transpose(0, 2, 1, 3, 4)
        for ti in range(2):
            for c in range(2):
                ref(f'{name}_t{ti}c{c}.f64', s[ti, c])
)PY"));
  for (const char* name : {"zct", "czt"}) {
    SCOPED_TRACE(name);
    const auto path = dir / (std::string(name) + ".ome.tif");
    const VolumeHeader h = read_tiff_header(path);
    EXPECT_EQ(h.dims, glm::ivec3(7, 6, 3));
    EXPECT_EQ(h.frames, 2);
    for (int t = 0; t < 2; ++t)
      for (int c = 0; c < 2; ++c)
        expect_reference_voxels(read_tiff(path, t, c),
                                dir / fmt::format("{}_t{}c{}.f64", name, t, c));
    // read_volume's frame is the time point, channel 0.
    expect_reference_voxels(read_volume(path, 1), dir / fmt::format("{}_t1c0.f64", name));
    expect_error([&] { read_tiff(path, 0, 2); }, {"channel 2", "0 to 1"});
    expect_error([&] { read_tiff(path, 2, 0); }, {"frame 2"});
  }
  // PhysicalSize units to mm; a missing one (z's unit, y's size) as OME's default µm and 1 mm.
  expect_spacing(read_tiff(dir / "zct.ome.tif"), {5e-3, 0.25e-3, 2.0e-3});
  expect_spacing(read_tiff(dir / "czt.ome.tif"), {1.0, 1.0, 3.0});
}

TEST(Tiff, ImageJHyperstackAndResolutionGiveSpacing) {
  SKIP_WITHOUT_TIFFFILE();
  TempDir dir;
  ASSERT_TRUE(test::run_tifffile_python(dir, R"PY(
data = np.arange(2 * 3 * 2 * 5 * 6, dtype='<u2').reshape(2, 3, 2, 5, 6)   # t, z, c, y, x
tifffile.imwrite('ij.tif', data, imagej=True, resolution=(1 / 0.5, 1 / 0.25),
                 metadata={'spacing': 2.5, 'unit': 'um', 'axes': 'TZCYX'})
with tifffile.TiffFile('ij.tif') as t:
    m = t.imagej_metadata
    assert (m['frames'], m['slices'], m['channels'], m['spacing'], m['unit']) == (2, 3, 2, 2.5, 'um')
    s = t.series[0].asarray()
    ref('ij_t1c1.f64', s[1, :, 1])
    ref('ij_t0c0.f64', s[0, :, 0])
d = np.zeros((2, 3, 4), '|u1')
tifffile.imwrite('inch.tif', d, resolution=(254, 127), resolutionunit='INCH')
tifffile.imwrite('cm.tif', d, resolution=(10, 20), resolutionunit='CENTIMETER')
tifffile.imwrite('none.tif', d, resolution=(10, 20), resolutionunit='NONE')
tifffile.imwrite('micron.tif', d, imagej=True, resolution=(4, 4),
                 metadata={'unit': '\\u00B5m', 'spacing': 3.0})
assert tifffile.TiffFile('micron.tif').imagej_metadata['unit'] == '\\u00B5m'
)PY"));
  const auto ij = dir / "ij.tif";
  EXPECT_EQ(read_tiff_header(ij).frames, 2);
  const VolumeData v = read_tiff(ij, 1, 1);
  EXPECT_EQ(v.dims, glm::ivec3(6, 5, 3));
  expect_reference_voxels(v, dir / "ij_t1c1.f64");
  expect_reference_voxels(read_volume(ij), dir / "ij_t0c0.f64");
  expect_spacing(v, {0.5e-3, 0.25e-3, 2.5e-3});
  expect_spacing(read_tiff(dir / "inch.tif"), {0.1, 0.2, 1.0});
  expect_spacing(read_tiff(dir / "cm.tif"), {1.0, 0.5, 1.0});
  expect_spacing(read_tiff(dir / "none.tif"), {1.0, 1.0, 1.0});
  // ImageJ's escaped "\u00B5m" is micrometres.
  expect_spacing(read_tiff(dir / "micron.tif"), {0.25e-3, 0.25e-3, 3.0e-3});
}

TEST(Tiff, FolderStackSortsNaturally) {
  SKIP_WITHOUT_TIFFFILE();
  TempDir dir;
  ASSERT_TRUE(test::run_tifffile_python(dir, R"PY(
os.makedirs('stack')
data = np.random.default_rng(9).integers(-3000, 3000, (12, 5, 6)).astype('<i2')
for z in [3, 11, 0, 7, 1, 10, 2, 5, 9, 4, 8, 6]:   # written out of order
    tifffile.imwrite(f'stack/z{z + 1}.tif', data[z], resolution=(20, 40),
                     resolutionunit='CENTIMETER', compression='zlib' if z % 2 else None)
ref('stack.f64', np.stack([tifffile.imread(f'stack/z{z + 1}.tif') for z in range(12)]))
os.makedirs('other')
tifffile.imwrite('other/a.tif', data[0])
tifffile.imwrite('other/b.tif', data[1, :4])
tifffile.imwrite('other/c.tif', data[2].astype('<f4'))
)PY"));
  const auto stack = dir / "stack";
  EXPECT_TRUE(is_volume_file(stack));
  EXPECT_FALSE(is_dicom_source(stack));
  const VolumeData v = read_volume(stack);
  EXPECT_EQ(v.dims, glm::ivec3(6, 5, 12));
  EXPECT_EQ(v.type(), VoxelType::i16);
  expect_reference_voxels(v, dir / "stack.f64");
  expect_spacing(v, {0.5, 0.25, 1.0});
  const VolumeData part = read_volume_region(stack, {{1, 1, 9}, {5, 4, 12}});
  EXPECT_EQ(part.value_at(0, 0, 0), v.value_at(1, 1, 9));
  EXPECT_EQ(part.value_at(3, 2, 2), v.value_at(4, 3, 11));
  EXPECT_EQ(read_volume_header(stack).dims, v.dims);
  expect_error([&] { read_volume(dir / "other"); }, {"b.tif", "page 0", "6 x 4", "6 x 5"});
  std::filesystem::remove(dir / "other/b.tif");
  expect_error([&] { read_volume(dir / "other"); }, {"c.tif", "page 0", "float32", "int16"});
  // A file that is no TIFF makes the folder no stack (a DICOM folder's files, say).
  dir.write("stack/notes.txt", "x");
  EXPECT_FALSE(is_tiff_folder(stack));
}

TEST(Tiff, NaturalOrder) {
  EXPECT_TRUE(natural_less("z2.tif", "z10.tif"));
  EXPECT_FALSE(natural_less("z10.tif", "z2.tif"));
  EXPECT_TRUE(natural_less("z002.tif", "z3.tif"));
  EXPECT_TRUE(natural_less("a.tif", "b.tif"));
  EXPECT_TRUE(natural_less("s1_2.tif", "s1_10.tif"));
  EXPECT_TRUE(natural_less("z1.tif", "z01.tif") != natural_less("z01.tif", "z1.tif"));
}

TEST(Tiff, ReducedResolutionPagesAndSubIfdsAreNotSlices) {
  SKIP_WITHOUT_TIFFFILE();
  TempDir dir;
  ASSERT_TRUE(test::run_tifffile_python(dir, R"PY(
data = np.arange(3 * 16 * 16, dtype='<u2').reshape(3, 16, 16)
with tifffile.TiffWriter('reduced.tif') as w:
    for z in range(3):
        w.write(data[z], contiguous=False, photometric='minisblack')
        w.write(data[z, ::2, ::2], subfiletype=1, photometric='minisblack')
with tifffile.TiffWriter('pyramid.ome.tif') as w:
    w.write(data, subifds=1, metadata={'axes': 'ZYX'}, photometric='minisblack')
    w.write(data[:, ::2, ::2], subfiletype=1, photometric='minisblack')
ref('data.f64', data)
assert len(tifffile.TiffFile('reduced.tif').pages) == 6
)PY"));
  expect_reference_voxels(read_tiff(dir / "reduced.tif"), dir / "data.f64");
  expect_reference_voxels(read_volume(dir / "pyramid.ome.tif"), dir / "data.f64");
}

}  // namespace
}  // namespace imx::detail
