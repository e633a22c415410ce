// DICOM RGB series (PhotometricInterpretation RGB, 3 samples of 8 bits, PlanarConfiguration 0 or
// 1) read as colour volumes, each voxel's colour at dcm2niix's place the colour dcm2niix's RGB24
// conversion holds there; a series picks them apart from a greyscale twin of one UID; YBR colour
// is refused naming it.
#include <cstring>
#include <filesystem>
#include <string>
#include <vector>

#include <fmt/format.h>
#include <gtest/gtest.h>
#include <glm/matrix.hpp>

#include "expect_error.hpp"
#include "intermix/dicom.hpp"
#include "intermix/error.hpp"
#include "intermix/io.hpp"
#include "pydicom_series.hpp"

namespace imx {
namespace {

using test::TempDir;

// Three series of three slices in one folder `in` (copies in `g`, `c`, `p` for dcm2niix):
// greyscale and RGB colour-by-pixel under one SeriesInstanceUID, RGB colour-by-plane under
// another; `y` holds a YBR_FULL series.
const char* kRgbSeries = R"PY(
import shutil
orient = rotated_axial(15)
pos = positions(orient, 3, 3.0)
for d in ('in', 'g', 'c', 'p', 'y'):
    os.makedirs(d, exist_ok=True)
def colour_planes(rows, cols, s):
    grey = (pixels(rows, cols, 1.0) // 16).clip(0, 255).astype(np.uint8)
    r = grey
    g = ((np.arange(rows * cols).reshape(rows, cols) * 7 + 40 * s) % 256).astype(np.uint8)
    b = (255 - grey).astype(np.uint8)
    return r, g, b
def rgb(planar, s, photometric='RGB'):
    def extra(ds):
        r, g, b = colour_planes(48, 40, s)
        ds.SamplesPerPixel = 3
        ds.PhotometricInterpretation = photometric
        ds.PlanarConfiguration = planar
        ds.SeriesNumber = 5 + planar
        ds.BitsAllocated = 8
        ds.BitsStored = 8
        ds.HighBit = 7
        del ds.RescaleSlope
        del ds.RescaleIntercept
        if planar == 0:
            ds.PixelData = np.stack([r, g, b], axis=-1).tobytes()
        else:
            ds.PixelData = np.stack([r, g, b], axis=0).tobytes()
    return extra
for s in range(3):
    write('g/G%02d.dcm' % s, 48, 40, pos[s], orient, pixels(48, 40, 1.0), '1.2.3.21', s + 1,
          manufacturer='SIEMENS')
    write('c/C%02d.dcm' % s, 48, 40, pos[s], orient, None, '1.2.3.21', 10 + s, rgb(0, s),
          manufacturer='SIEMENS')
    write('p/P%02d.dcm' % s, 48, 40, pos[s], orient, None, '1.2.3.23', 20 + s, rgb(1, s),
          manufacturer='SIEMENS')
    write('y/Y%02d.dcm' % s, 48, 40, pos[s], orient, None, '1.2.3.24', 30 + s,
          rgb(0, s, 'YBR_FULL'), manufacturer='SIEMENS')
for d in ('g', 'c', 'p'):
    for f in os.listdir(d):
        shutil.copy(os.path.join(d, f), os.path.join('in', f))
)PY";

// Every voxel of `mine` lies on a voxel of `ref` (to 0.01 mm) with the same colour and scalar.
void expect_same_colours(const VolumeData& mine, const VolumeData& ref, const std::string& what) {
  ASSERT_TRUE(mine.colours) << what << ": read without colours";
  ASSERT_TRUE(ref.colours) << what << ": dcm2niix's conversion is not RGB";
  const glm::dmat4 to_ref = glm::inverse(ref.index_to_world) * mine.index_to_world;
  int differ = 0;
  for (int k = 0; k < mine.dims.z; ++k)
    for (int j = 0; j < mine.dims.y; ++j)
      for (int i = 0; i < mine.dims.x; ++i) {
        const glm::dvec3 r = glm::dvec3(to_ref * glm::dvec4(i, j, k, 1.0));
        const glm::ivec3 n(glm::round(r));
        ASSERT_LT(glm::length(r - glm::dvec3(n)), 0.01)
            << what << ": voxel " << i << "," << j << "," << k << " is off dcm2niix's grid";
        ASSERT_TRUE(glm::all(glm::greaterThanEqual(n, glm::ivec3(0))) &&
                    glm::all(glm::lessThan(n, ref.dims)))
            << what;
        const size_t a = (static_cast<size_t>(k) * mine.dims.y + j) * mine.dims.x + i;
        const size_t b = (static_cast<size_t>(n.z) * ref.dims.y + n.y) * ref.dims.x + n.x;
        if (std::memcmp(mine.colours->rgb.data() + 3 * a, ref.colours->rgb.data() + 3 * b, 3) !=
                0 ||
            mine.value_at(i, j, k) != ref.value_at(n.x, n.y, n.z))
          ++differ;
      }
  EXPECT_EQ(differ, 0) << what << ": voxels whose colour differs from dcm2niix's";
}

TEST(DicomColour, RgbSeriesReadAsDcm2niixConvertsThem) {
  SKIP_WITHOUT_PYDICOM_AND_DCM2NIIX();
  TempDir dir;
  ASSERT_TRUE(test::run_pydicom(dir, kRgbSeries));
  for (const char* d : {"c", "p"}) {
    ASSERT_TRUE(test::run_dcm2niix(dir / d, dir / "out", d));
    const DicomVolume mine = read_dicom(dir / d);
    EXPECT_EQ(mine.volume.dims, glm::ivec3(40, 48, 3)) << d;
    expect_same_colours(mine.volume, read_volume(dir / "out" / (std::string(d) + ".nii")),
                        fmt::format("planar configuration {}", d[0] == 'c' ? 0 : 1));
  }
}

TEST(DicomColour, SeriesPicksTheRgbOnesApartFromTheirGreyTwin) {
  SKIP_WITHOUT_PYDICOM_AND_DCM2NIIX();
  TempDir dir;
  ASSERT_TRUE(test::run_pydicom(dir, kRgbSeries));
  const std::vector<DicomSeriesInfo> series = list_dicom_series(dir / "in");
  ASSERT_EQ(series.size(), 3u);
  const VolumeData c = read_dicom(dir / "c").volume, p = read_dicom(dir / "p").volume;
  int grey = 0, colour = 0;
  for (const DicomSeriesInfo& s : series) {
    DicomReadOptions o;
    o.series = s.id;  // what --series passes
    const DicomVolume d = read_dicom(dir / "in", o);
    EXPECT_EQ(d.volume.dims, glm::ivec3(40, 48, 3)) << s.id;
    if (!d.volume.colours) {
      ++grey;
      continue;
    }
    ++colour;
    // Colour-by-pixel and colour-by-plane hold the same colours: either reads as its folder.
    const VolumeData& twin = d.volume.colours->rgb == c.colours->rgb ? c : p;
    EXPECT_EQ(d.volume.colours->rgb, twin.colours->rgb) << s.id;
    EXPECT_EQ(d.volume.index_to_world, twin.index_to_world) << s.id;
  }
  EXPECT_EQ(grey, 1);
  EXPECT_EQ(colour, 2);
}

TEST(DicomColour, YbrColourIsRefusedNamingIt) {
  SKIP_WITHOUT_PYDICOM_AND_DCM2NIIX();
  TempDir dir;
  ASSERT_TRUE(test::run_pydicom(dir, kRgbSeries));
  test::expect_error([&] { read_dicom(dir / "y"); }, {"YBR_FULL", "(0028,0004)"});
}

}  // namespace
}  // namespace imx
