// Diffusion series whose vendor tags the reader must turn as dcm2niix does, built with pydicom
// from a real slice (tests/support/pydicom_series.hpp) and converted by dcm2niix beside
// intermix: b-values, directions (in world space, through each program's own affine) and which
// images are diffusion data. Skipped without pydicom, dcm2niix or ../shared/data.
#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <string>
#include <vector>

#include <fmt/format.h>
#include <gtest/gtest.h>
#include <glm/geometric.hpp>
#include <glm/matrix.hpp>

#include "fsl_diffusion_files.hpp"
#include "intermix/dicom.hpp"
#include "intermix/error.hpp"
#include "intermix/io.hpp"
#include "io/dicom/dicom_volumes.hpp"
#include "pydicom_series.hpp"

namespace imx {
namespace {

namespace fs = std::filesystem;
using test::bvec_world;
using test::read_rows;
using test::TempDir;

// The world direction of a frame label (along the volume's i, j, k axes).
glm::dvec3 label_world(const FrameLabel& l, const glm::dmat4& index_to_world) {
  const glm::dvec3 v = l.b_vector.value_or(glm::dvec3(0.0));
  const glm::dmat3 m(index_to_world);
  const glm::dvec3 w =
      glm::normalize(m[0]) * v.x + glm::normalize(m[1]) * v.y + glm::normalize(m[2]) * v.z;
  return glm::length(w) > 1e-9 ? glm::normalize(w) : glm::dvec3(0.0);
}

// Every frame's b-value and world direction equal dcm2niix's `name`.bval/.bvec in `out`.
void expect_labels_equal_dcm2niix(const DicomVolume& d, const fs::path& out,
                                  const std::string& name) {
  const auto bval = read_rows(out / (name + ".bval"));
  const auto bvec = read_rows(out / (name + ".bvec"));
  ASSERT_EQ(bval.size(), 1u) << "dcm2niix wrote no .bval";
  ASSERT_EQ(bvec.size(), 3u);
  const VolumeHeader ref = read_volume_header(out / (name + ".nii"));
  ASSERT_EQ(d.frame_labels.size(), bval[0].size());
  for (size_t f = 0; f < bval[0].size(); ++f) {
    const FrameLabel& l = d.frame_labels[f];
    ASSERT_TRUE(l.b_value.has_value()) << "frame " << f;
    EXPECT_NEAR(*l.b_value, bval[0][f], 0.5) << "frame " << f;
    const glm::dvec3 theirs =
        bvec_world(glm::dvec3(bvec[0][f], bvec[1][f], bvec[2][f]), ref.index_to_world);
    const glm::dvec3 ours = label_world(l, d.volume.index_to_world);
    EXPECT_LT(glm::length(ours - theirs), 1e-3)
        << "frame " << f << ": ours " << ours.x << "," << ours.y << "," << ours.z << " dcm2niix's "
        << theirs.x << "," << theirs.y << "," << theirs.z;
  }
}

// A GE DWI of four slices of 48 x 40: a b = 0 volume, four directions, one of b = 2000 with a
// vector of length 0.5 (b scaled to 500) and one of b = 1000 without a direction (dcm2niix: b =
// 0); the gradient in GE's (0019,10BB-BD), the b-value in (0043,1039); `orientation` and `phase`
// vary.
std::string ge_dwi_script(const std::string& orientation, const std::string& phase) {
  return fmt::format(R"PY(
orient = {}
dirs = [(0, 0, 0, 0), (1000, 0.8, 0.36, 0.48), (1000, -0.3, 0.9, 0.3162), (1000, 0.6, 0.0, -0.8),
        (1000, 0.0, -0.6, 0.8), (2000, 0.4, 0.18, 0.24), (1000, 0, 0, 0)]
pos = positions(orient, 4, 3.0)
os.makedirs('in', exist_ok=True)
inst = 0
for v, (b, x, y, z) in enumerate(dirs):
    for s in range(4):
        inst += 1
        def extra(ds, b=b, x=x, y=y, z=z):
            ds.InPlanePhaseEncodingDirection = '{}'
            ds.add_new(0x00190010, 'LO', 'GEMS_ACQU_01')
            ds.add_new(0x001910BB, 'DS', str(x))
            ds.add_new(0x001910BC, 'DS', str(y))
            ds.add_new(0x001910BD, 'DS', str(z))
            ds.add_new(0x00430010, 'LO', 'GEMS_PARM_01')
            ds.add_new(0x00431039, 'IS', [b, 8, 0, 0])
        write('in/IM%04d.dcm' % inst, 48, 40, pos[s], orient, pixels(48, 40, 1.0 / (1 + v) + 0.05 * s),
              '1.2.826.0.1.3680043.8.498.77', inst, extra)
)PY",
                     orientation, phase);
}

struct GeCase {
  const char* name;
  const char* orientation;  // Python expression
  const char* phase;
};

class GeDiffusion : public ::testing::TestWithParam<GeCase> {};

TEST_P(GeDiffusion, DirectionsEqualDcm2niixs) {
  SKIP_WITHOUT_PYDICOM_AND_DCM2NIIX();
  const GeCase c = GetParam();
  TempDir dir;
  ASSERT_TRUE(test::run_pydicom(dir, ge_dwi_script(c.orientation, c.phase)));
  ASSERT_TRUE(test::run_dcm2niix(dir / "in", dir / "out", "dwi"));
  const DicomVolume d = read_dicom(dir / "in");
  ASSERT_EQ(d.frames, 7);
  expect_labels_equal_dcm2niix(d, dir / "out", "dwi");
}

INSTANTIATE_TEST_SUITE_P(
    Orientations, GeDiffusion,
    ::testing::Values(GeCase{"axial43col", "rotated_axial(43)", "COL"},
                      GeCase{"axial43row", "rotated_axial(43)", "ROW"},
                      GeCase{"axialMinus20", "rotated_axial(-20)", "COL"},
                      GeCase{"axialFlipped", "[1, 0, 0, 0, -1, 0]", "COL"},
                      GeCase{"sagittal", "[0, 1, 0, 0, 0, -1]", "COL"},
                      GeCase{"coronal", "[1, 0, 0, 0, 0, -1]", "COL"},
                      GeCase{"obliqueSagittalRow", "[0, 0.7071, -0.7071, 0, 0.7071, 0.7071]",
                             "ROW"}),
    [](const ::testing::TestParamInfo<GeCase>& info) { return std::string(info.param.name); });

// Where voxel (i, j, k) of `mine` lies in `ref`: both grids must coincide to 0.01 mm there.
// Every voxel's value equals the reference's at the same place.
void expect_same_voxels(const VolumeData& mine, const VolumeData& ref, const std::string& what) {
  const glm::dmat4 to_ref = glm::inverse(ref.index_to_world) * mine.index_to_world;
  int differ = 0;
  for (int k = 0; k < mine.dims.z; ++k)
    for (int j = 0; j < mine.dims.y; ++j)
      for (int i = 0; i < mine.dims.x; ++i) {
        const glm::dvec3 r = glm::dvec3(to_ref * glm::dvec4(i, j, k, 1.0));
        const glm::ivec3 n(glm::round(r));
        ASSERT_LT(glm::length(r - glm::dvec3(n)), 0.01)
            << what << ": voxel " << i << "," << j << "," << k << " lies at " << r.x << "," << r.y
            << "," << r.z << " of the reference grid";
        ASSERT_TRUE(n.x >= 0 && n.y >= 0 && n.z >= 0 && n.x < ref.dims.x && n.y < ref.dims.y &&
                    n.z < ref.dims.z)
            << what;
        if (mine.value_at(i, j, k) != ref.value_at(n.x, n.y, n.z)) ++differ;
      }
  EXPECT_EQ(differ, 0) << what;
}

bool has_note(const DicomVolume& d, const std::string& part) {
  return std::any_of(d.notes.begin(), d.notes.end(),
                     [&](const std::string& n) { return n.find(part) != std::string::npos; });
}

// Five volumes (b = 0, three directions, one derived) of `vendor`'s tags; `derived_type` gives
// the derived volume an ImageType of its own.
std::string derived_script(const std::string& vendor, bool derived_type) {
  return fmt::format(R"PY(
vendor = '{}'
derived_type = {}
orient = rotated_axial(10)
dirs = [(0, 0, 0, 0, 'N'), (1000, 0.8, 0.36, 0.48, 'O'), (1000, -0.3, 0.9, 0.3162, 'O'),
        (1000, 0.6, 0.0, -0.8, 'O'), (1000, 0, 0, 0, 'I')]
pos = positions(orient, 4, 3.0)
os.makedirs('in', exist_ok=True)
inst = 0
for v, (b, x, y, z, kind) in enumerate(dirs):
    for s in range(4):
        inst += 1
        def extra(ds, b=b, x=x, y=y, z=z, kind=kind):
            if vendor == 'philips':
                ds.add_new(0x20010010, 'LO', 'Philips Imaging DD 001')
                ds.add_new(0x20011003, 'FL', float(b))
                ds.add_new(0x20011004, 'CS', kind)
                ds.add_new(0x20050010, 'LO', 'Philips MR Imaging DD 001')
                ds.add_new(0x200510B0, 'FL', float(x))
                ds.add_new(0x200510B1, 'FL', float(y))
                ds.add_new(0x200510B2, 'FL', float(z))
            else:
                ds.add_new(0x00190010, 'LO', 'SIEMENS MR HEADER')
                ds.add_new(0x0019100C, 'IS', b)
                if kind == 'O':
                    ds.add_new(0x0019100E, 'FD', [float(x), float(y), float(z)])
            if kind == 'I' and derived_type:
                ds.ImageType = ['DERIVED', 'PRIMARY', 'DIFFUSION', 'TRACEW', 'ND']
        write('in/IM%04d.dcm' % inst, 48, 40, pos[s], orient, pixels(48, 40, 1.0 / (1 + v) + 0.05 * s),
              '1.2.826.0.1.3680043.8.498.78', inst, extra,
              manufacturer='Philips Medical Systems' if vendor == 'philips' else 'SIEMENS')
)PY",
                     vendor, derived_type ? "True" : "False");
}

// Philips' isotropic image (direction 'I', b > 0, no direction) among the DWI's images: dcm2niix
// leaves it out of the DWI; so does intermix, which lists it as a series of its own.
TEST(DerivedDiffusion, PhilipsIsotropicImageIsLeftOutAsDcm2niixLeavesItOut) {
  SKIP_WITHOUT_PYDICOM_AND_DCM2NIIX();
  TempDir dir;
  ASSERT_TRUE(test::run_pydicom(dir, derived_script("philips", false)));
  ASSERT_TRUE(test::run_dcm2niix(dir / "in", dir / "out", "dwi"));
  const VolumeHeader ref = read_volume_header(dir / "out" / "dwi.nii");
  const DicomVolume d = read_dicom(dir / "in");
  EXPECT_EQ(d.frames, ref.frames);
  // Its files are a series of their own (4 slices, no volumes); a file holding both kinds of
  // image would drop it with a note instead.
  const std::vector<DicomSeriesInfo> series = list_dicom_series(dir / "in");
  ASSERT_EQ(series.size(), 2u);
  const DicomSeriesInfo& other = series[0].id == d.series.id ? series[1] : series[0];
  EXPECT_EQ(other.slices, 4);
  expect_labels_equal_dcm2niix(d, dir / "out", "dwi");
  for (int f = 0; f < ref.frames; ++f) {
    DicomReadOptions o;
    o.frame = f;
    expect_same_voxels(read_dicom(dir / "in", o).volume, read_volume(dir / "out" / "dwi.nii", f),
                       fmt::format("frame {}", f));
  }
}

// Trace images (ImageType DERIVED ... TRACEW) sharing the DWI's SeriesInstanceUID: dcm2niix
// converts them apart (the trace as a volume of its own, b = 1000 and no direction); intermix
// lists them as a series of their own, and the DWI's labels equal dcm2niix's.
TEST(DerivedDiffusion, SiemensTraceImagesAreASeriesOfTheirOwnAsInDcm2niix) {
  SKIP_WITHOUT_PYDICOM_AND_DCM2NIIX();
  TempDir dir;
  ASSERT_TRUE(test::run_pydicom(dir, derived_script("siemens", true)));
  ASSERT_TRUE(test::run_dcm2niix(dir / "in", dir / "out", "dwi"));
  // dcm2niix names the second series it writes dwia: the larger is the DWI.
  const VolumeHeader a = read_volume_header(dir / "out" / "dwi.nii");
  const VolumeHeader b = read_volume_header(dir / "out" / "dwia.nii");
  const std::string dwi = a.frames > b.frames ? "dwi" : "dwia";
  const std::string trace = a.frames > b.frames ? "dwia" : "dwi";
  const std::vector<DicomSeriesInfo> series = list_dicom_series(dir / "in");
  ASSERT_EQ(series.size(), 2u);
  EXPECT_NE(series[0].id, series[1].id);
  const DicomVolume d = read_dicom(dir / "in");
  EXPECT_EQ(d.frames, std::max(a.frames, b.frames));
  expect_labels_equal_dcm2niix(d, dir / "out", dwi);
  DicomReadOptions other;
  other.series = series[0].id == d.series.id ? series[1].id : series[0].id;
  const DicomVolume t = read_dicom(dir / "in", other);
  expect_same_voxels(t.volume, read_volume(dir / "out" / (trace + ".nii")), "trace");
}

// A trace series of its own (b = 0 and 1000, no directions): dcm2niix writes b-values and zero
// vectors; so do intermix's labels.
TEST(DerivedDiffusion, TraceSeriesLabelsEqualDcm2niixs) {
  SKIP_WITHOUT_PYDICOM_AND_DCM2NIIX();
  TempDir dir;
  ASSERT_TRUE(test::run_pydicom(dir, R"PY(
orient = rotated_axial(10)
pos = positions(orient, 4, 3.0)
os.makedirs('in', exist_ok=True)
inst = 0
for v, b in enumerate([0, 1000]):
    for s in range(4):
        inst += 1
        def extra(ds, b=b):
            ds.ImageType = ['DERIVED', 'PRIMARY', 'DIFFUSION', 'TRACEW', 'ND']
            ds.add_new(0x00190010, 'LO', 'SIEMENS MR HEADER')
            ds.add_new(0x0019100C, 'IS', b)
        write('in/IM%04d.dcm' % inst, 48, 40, pos[s], orient, pixels(48, 40, 1.0 / (1 + v)),
              '1.2.3.9', inst, extra, manufacturer='SIEMENS')
)PY"));
  ASSERT_TRUE(test::run_dcm2niix(dir / "in", dir / "out", "tr"));
  const DicomVolume d = read_dicom(dir / "in");
  ASSERT_EQ(d.frames, 2);
  expect_labels_equal_dcm2niix(d, dir / "out", "tr");
}

// GE epi_pepolar alternating forward and reverse volumes by temporal position (user data 12 = 2:
// the odd ones reversed; 3: the even ones): dcm2niix converts the odd and the even time points
// as two series, mirroring the reversed ones' rows; intermix lists the same two series, whose
// every voxel equals dcm2niix's.
TEST(GePepolar, AlternatingPolaritiesAreTwoSeriesAsInDcm2niix) {
  SKIP_WITHOUT_PYDICOM_AND_DCM2NIIX();
  for (const char* user_data : {"2", "3"}) {
    TempDir dir;
    ASSERT_TRUE(test::run_pydicom(dir, fmt::format(R"PY(
orient = rotated_axial(0)
pos = positions(orient, 4, 3.0)
os.makedirs('in', exist_ok=True)
inst = 0
for v in range(4):
    for s in range(4):
        inst += 1
        def extra(ds, v=v):
            ds.AcquisitionTime = '1200%02d' % (v * 4)
            ds.TemporalPositionIdentifier = v + 1
            ds.NumberOfTemporalPositions = 4
            ds.add_new(0x00190010, 'LO', 'GEMS_ACQU_01')
            ds.add_new(0x0019109C, 'LO', 'epi_pepolar')
            ds.add_new(0x001910B3, 'DS', '{}')
        write('in/IM%04d.dcm' % inst, 48, 40, pos[s], orient, pixels(48, 40, 1.0 / (1 + v) + 0.05 * s),
              '1.2.3.10', inst, extra)
)PY",
                                                   user_data)));
    ASSERT_TRUE(test::run_dcm2niix(dir / "in", dir / "out", "pe"));
    const std::vector<DicomSeriesInfo> series = list_dicom_series(dir / "in");
    ASSERT_EQ(series.size(), 2u) << "user data " << user_data;
    // dcm2niix writes the odd time points (the first) as pe, the even ones as pea.
    const char* names[] = {"pe", "pea"};
    for (int part = 0; part < 2; ++part) {
      const fs::path ref = dir / "out" / (std::string(names[part]) + ".nii");
      const VolumeHeader rh = read_volume_header(ref);
      DicomReadOptions o;
      o.series = series[static_cast<size_t>(part)].id;
      const VolumeHeader h = read_dicom_header(dir / "in", o);
      ASSERT_EQ(h.frames, rh.frames);
      for (int f = 0; f < rh.frames; ++f) {
        o.frame = f;
        expect_same_voxels(read_dicom(dir / "in", o).volume, read_volume(ref, f),
                           fmt::format("user data {} {} frame {}", user_data, names[part], f));
      }
    }
  }
}

// A grey series and its RGB twin under one SeriesInstanceUID: two series with ids of their own;
// the grey one reads as greyscale, the RGB one as a colour volume (dicom_colour_test.cpp).
TEST(RgbTwin, GreyAndRgbSeriesOfOneUidHaveDistinctIds) {
  SKIP_WITHOUT_PYDICOM_AND_DCM2NIIX();
  TempDir dir;
  ASSERT_TRUE(test::run_pydicom(dir, R"PY(
orient = rotated_axial(0)
pos = positions(orient, 3, 3.0)
os.makedirs('in', exist_ok=True)
for s in range(3):
    write('in/G%02d.dcm' % s, 48, 40, pos[s], orient, pixels(48, 40, 1.0), '1.2.3.11', s + 1,
          manufacturer='SIEMENS')
    def rgb(ds, s=s):
        grey = (pixels(48, 40, 1.0) // 16).clip(0, 255).astype(np.uint8)
        ds.SamplesPerPixel = 3
        ds.PhotometricInterpretation = 'RGB'
        ds.PlanarConfiguration = 0
        ds.BitsAllocated = 8
        ds.BitsStored = 8
        ds.HighBit = 7
        del ds.RescaleSlope
        del ds.RescaleIntercept
        ds.PixelData = np.stack([grey, grey // 2, 255 - grey], axis=-1).tobytes()
    write('in/C%02d.dcm' % s, 48, 40, pos[s], orient, None, '1.2.3.11', 10 + s, rgb,
          manufacturer='SIEMENS')
)PY"));
  const std::vector<DicomSeriesInfo> series = list_dicom_series(dir / "in");
  ASSERT_EQ(series.size(), 2u);
  EXPECT_NE(series[0].id, series[1].id);
  int colour = 0;
  for (const DicomSeriesInfo& s : series) {
    DicomReadOptions o;
    o.series = s.id;
    EXPECT_EQ(s.slices, 3) << s.id;
    const DicomVolume d = read_dicom(dir / "in", o);
    EXPECT_EQ(d.volume.dims, glm::ivec3(40, 48, 3));
    colour += d.volume.colours != nullptr;
  }
  EXPECT_EQ(colour, 1);
}

// A series without ImagePositionPatient (as some UIH DTI series come): dcm2niix stacks every
// image in acquisition order along the patient axes, centred on the origin; intermix places
// them the same (every voxel at dcm2niix's place with its value), with a note.
TEST(NoPositions, SeriesIsPlacedAsDcm2niixPlacesIt) {
  SKIP_WITHOUT_PYDICOM_AND_DCM2NIIX();
  TempDir dir;
  ASSERT_TRUE(test::run_pydicom(dir, R"PY(
orient = rotated_axial(30)
os.makedirs('in', exist_ok=True)
inst = 0
for v in range(2):
    for s in range(4):
        inst += 1
        def extra(ds, s=s):
            ds.SliceLocation = 10 + 3 * s
            ds.SpacingBetweenSlices = 4.0
        write('in/IM%04d.dcm' % inst, 48, 40, None, orient, pixels(48, 40, 1.0 / (1 + v) + 0.05 * s),
              '1.2.3.12', inst, extra, manufacturer='UIH')
)PY"));
  ASSERT_TRUE(test::run_dcm2niix(dir / "in", dir / "out", "np"));
  // dcm2niix writes no sform or qform (it knows no placement): nibabel's reading of its file,
  // the volume centred on the origin, is the placement to match.
  if (std::system("/usr/bin/python3 -c 'import nibabel' >/dev/null 2>&1") != 0)
    GTEST_SKIP() << "/usr/bin/python3 has no nibabel";
  ASSERT_TRUE(test::run_pydicom(dir, R"PY(
import nibabel as nib
np.savetxt('out/np.affine', np.diag([-1.0, -1.0, 1.0, 1.0]) @ nib.load('out/np.nii').affine)
)PY"));
  const auto affine = read_rows(dir / "out" / "np.affine");
  ASSERT_EQ(affine.size(), 4u);
  const DicomVolume d = read_dicom(dir / "in");
  EXPECT_TRUE(has_note(d, "no ImagePositionPatient")) << "no note on the placement";
  VolumeData ref = read_volume(dir / "out" / "np.nii");
  for (int r = 0; r < 4; ++r)
    for (int c = 0; c < 4; ++c) ref.index_to_world[c][r] = affine[r][c];
  ASSERT_EQ(d.volume.dims, ref.dims);
  expect_same_voxels(d.volume, ref, "stack");
}

// Derived images inside the files of the DWI (an enhanced multi-frame file holds every frame,
// so they cannot become a series of their own): left out of the volumes with a note, as dcm2niix
// leaves Philips' isotropic volume out (PhilipsIsotropicImageIsLeftOutAsDcm2niixLeavesItOut).
TEST(DerivedDiffusion, DerivedFramesOfOneFileAreLeftOutWithANote) {
  std::vector<detail::DicomFrame> images;
  for (int v = 0; v < 3; ++v)
    for (int s = 0; s < 2; ++s) {
      detail::DicomFrame f;
      f.file = "enhanced.dcm";
      f.frame = v * 2 + s;
      f.position = glm::dvec3(0, 0, 3 * s);
      f.row_direction = glm::dvec3(1, 0, 0);
      f.column_direction = glm::dvec3(0, 1, 0);
      f.b_value = v == 0 ? 0.0 : 1000.0;
      f.gradient = v == 1 ? glm::dvec3(0.6, 0, 0.8) : glm::dvec3(0.0);
      f.derived_diffusion = v == 2;
      images.push_back(f);
    }
  const detail::DicomVolumes d = detail::split_volumes(images, "enhanced.dcm");
  ASSERT_EQ(d.volumes.size(), 2u);
  ASSERT_EQ(d.notes.size(), 1u);
  EXPECT_NE(d.notes[0].find("2 derived diffusion images"), std::string::npos) << d.notes[0];
  for (const auto& volume : d.volumes)
    for (const detail::DicomFrame& f : volume) EXPECT_FALSE(f.derived_diffusion);
}

}  // namespace
}  // namespace imx
