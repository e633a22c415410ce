// Multi-volume DICOM series (../shared/data/dicom4d: Siemens mosaics, XA30 enhanced ASL and DWI)
// against dcm2niix's 4-D conversions in dicom4d/ref: every frame at the same world positions,
// the same frame order, the same b-values and directions. Skipped without ../shared/data.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <glm/geometric.hpp>
#include <glm/matrix.hpp>

#include "fsl_diffusion_files.hpp"
#include "intermix/dicom.hpp"
#include "intermix/io.hpp"
#include "shared_data.hpp"

namespace imx {
namespace {

namespace fs = std::filesystem;
using test::bvec_world;
using test::read_rows;

fs::path dicom4d(const std::string& name) {
  return test::shared_data("dicom4d") / name;
}

// Where voxel (i, j, k) of `mine` lies in `ref`'s grid: a signed permutation plus an integer
// offset, checked to 0.01 mm at the grid's corners.
struct IndexMap {
  glm::dmat4 mine_to_ref{1.0};
};

IndexMap index_map(const VolumeData& mine, const VolumeData& ref) {
  IndexMap m;
  m.mine_to_ref = glm::inverse(ref.index_to_world) * mine.index_to_world;
  for (int c = 0; c < 8; ++c) {
    const glm::dvec3 idx((c & 1) ? mine.dims.x - 1 : 0, (c & 2) ? mine.dims.y - 1 : 0,
                         (c & 4) ? mine.dims.z - 1 : 0);
    const glm::dvec3 r = glm::dvec3(m.mine_to_ref * glm::dvec4(idx, 1.0));
    const glm::dvec3 rounded = glm::round(r);
    const glm::dvec3 world_mine = glm::dvec3(mine.index_to_world * glm::dvec4(idx, 1.0));
    const glm::dvec3 world_ref = glm::dvec3(ref.index_to_world * glm::dvec4(rounded, 1.0));
    EXPECT_LT(glm::length(world_mine - world_ref), 0.01) << "corner " << c;
    for (int a = 0; a < 3; ++a) {
      EXPECT_GE(rounded[a], 0);
      EXPECT_LT(rounded[a], ref.dims[a]);
    }
  }
  return m;
}

struct Agreement {
  double correlation = 0.0, median_abs_difference = 0.0;
};

Agreement compare_frames(const VolumeData& mine, const VolumeData& ref, const IndexMap& map) {
  std::vector<double> a, b, diff;
  for (int k = 0; k < mine.dims.z; ++k)
    for (int j = 0; j < mine.dims.y; ++j)
      for (int i = 0; i < mine.dims.x; ++i) {
        const glm::ivec3 r(glm::round(glm::dvec3(map.mine_to_ref * glm::dvec4(i, j, k, 1.0))));
        a.push_back(mine.value_at(i, j, k));
        b.push_back(ref.value_at(r.x, r.y, r.z));
        diff.push_back(std::abs(a.back() - b.back()));
      }
  const double n = static_cast<double>(a.size());
  double ma = 0, mb = 0;
  for (size_t i = 0; i < a.size(); ++i) {
    ma += a[i] / n;
    mb += b[i] / n;
  }
  double sab = 0, saa = 0, sbb = 0;
  for (size_t i = 0; i < a.size(); ++i) {
    sab += (a[i] - ma) * (b[i] - mb);
    saa += (a[i] - ma) * (a[i] - ma);
    sbb += (b[i] - mb) * (b[i] - mb);
  }
  std::nth_element(diff.begin(), diff.begin() + diff.size() / 2, diff.end());
  return {sab / std::sqrt(saa * sbb), diff[diff.size() / 2]};
}

class Dicom4d : public ::testing::TestWithParam<const char*> {};

TEST_P(Dicom4d, EveryFrameMatchesDcm2niixInOrderAndPlace) {
  const std::string name = GetParam();
  SKIP_WITHOUT_SHARED_DATA(dicom4d(name));
  const fs::path ref_file = dicom4d("ref/" + name + ".nii.gz");
  const VolumeHeader ref_header = read_volume_header(ref_file);
  const VolumeHeader header = read_dicom_header(dicom4d(name));
  ASSERT_GT(ref_header.frames, 1);
  ASSERT_EQ(header.frames, ref_header.frames);
  ASSERT_EQ(header.frame_labels.size(), static_cast<size_t>(header.frames));
  double worst_correlation = 1.0, worst_median = 0.0;
  for (int f = 0; f < header.frames; ++f) {
    DicomReadOptions options;
    options.frame = f;
    const DicomVolume d = read_dicom(dicom4d(name), options);
    const VolumeData ref = read_volume(ref_file, f);
    ASSERT_EQ(d.frames, header.frames);
    ASSERT_EQ(d.volume.voxel_count(), ref.voxel_count()) << "frame " << f;
    const IndexMap map = index_map(d.volume, ref);
    const Agreement agree = compare_frames(d.volume, ref, map);
    EXPECT_GE(agree.correlation, 0.9999) << name << " frame " << f;
    EXPECT_EQ(agree.median_abs_difference, 0.0) << name << " frame " << f;
    worst_correlation = std::min(worst_correlation, agree.correlation);
    worst_median = std::max(worst_median, agree.median_abs_difference);
  }
  // For docs/clinical_data.md.
  std::printf(
      "%s: %d frames of %dx%dx%d, lowest correlation %.6f, largest median |difference| %g\n",
      name.c_str(), header.frames, header.dims.x, header.dims.y, header.dims.z, worst_correlation,
      worst_median);
}

INSTANTIATE_TEST_SUITE_P(SharedSeries, Dicom4d,
                         ::testing::Values("mosaic-ep2d_Asc_2", "mosaic-cmrr_Asc_6", "xa30-asl-25",
                                           "xa30-dwi-10"));

TEST(Dicom4dDiffusion, BValuesAndDirectionsEqualDcm2niixs) {
  const std::string name = "xa30-dwi-10";
  SKIP_WITHOUT_SHARED_DATA(dicom4d(name));
  const std::vector<std::vector<double>> bval = read_rows(dicom4d("ref/" + name + ".bval"));
  const std::vector<std::vector<double>> bvec = read_rows(dicom4d("ref/" + name + ".bvec"));
  ASSERT_EQ(bval.size(), 1u);
  ASSERT_EQ(bvec.size(), 3u);
  const VolumeHeader ref = read_volume_header(dicom4d("ref/" + name + ".nii.gz"));
  const DicomVolume d = read_dicom(dicom4d(name));
  ASSERT_EQ(d.frame_labels.size(), bval[0].size());
  int directions = 0;
  for (size_t f = 0; f < bval[0].size(); ++f) {
    const FrameLabel& l = d.frame_labels[f];
    ASSERT_TRUE(l.b_value.has_value()) << f;
    EXPECT_NEAR(*l.b_value, bval[0][f], 0.5) << f;
    const glm::dvec3 theirs =
        bvec_world(glm::dvec3(bvec[0][f], bvec[1][f], bvec[2][f]), ref.index_to_world);
    const glm::dvec3 v = l.b_vector.value_or(glm::dvec3(0.0));
    // Labels are along the volume's own axes (the convention of .bvec without its x flip).
    const glm::dmat3 m(d.volume.index_to_world);
    glm::dvec3 ours =
        glm::normalize(m[0]) * v.x + glm::normalize(m[1]) * v.y + glm::normalize(m[2]) * v.z;
    if (glm::length(theirs) < 1e-6) {
      EXPECT_LT(glm::length(ours), 1e-6) << f;
      continue;
    }
    ours = glm::normalize(ours);
    EXPECT_GT(std::abs(glm::dot(ours, theirs)), 0.9999) << "frame " << f;
    EXPECT_GT(glm::dot(ours, theirs), 0.0) << "frame " << f;
    ++directions;
  }
  EXPECT_EQ(directions, 20);
}

}  // namespace
}  // namespace imx
