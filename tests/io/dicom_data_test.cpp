// DICOM reading checked against the shared data and dcm2niix's conversions of it (skipped when
// ../shared/data is absent).
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <random>
#include <vector>

#include <fmt/format.h>
#include <gtest/gtest.h>
#include <glm/geometric.hpp>
#include <glm/mat4x4.hpp>

#include "intermix/dicom.hpp"
#include "intermix/error.hpp"
#include "intermix/io.hpp"
#include "io/dicom/dicom_reader.hpp"
#include "shared_data.hpp"
#include "temp_dir.hpp"

namespace imx {
namespace {

namespace fs = std::filesystem;

using test::shared_data;

glm::dvec3 world(const glm::dmat4& m, glm::dvec3 idx) {
  return glm::dvec3(m * glm::dvec4(idx, 1));
}

// Trilinear value at continuous index `p`; nullopt outside the grid.
std::optional<double> sample(const VolumeData& v, glm::dvec3 p) {
  glm::dvec3 f = glm::floor(p);
  if (f.x < 0 || f.y < 0 || f.z < 0 || p.x > v.dims.x - 1 || p.y > v.dims.y - 1 ||
      p.z > v.dims.z - 1)
    return std::nullopt;
  glm::ivec3 i0(f), i1 = glm::min(i0 + 1, v.dims - 1);
  glm::dvec3 t = p - f;
  double out = 0.0;
  for (int c = 0; c < 8; ++c) {
    glm::ivec3 q((c & 1) ? i1.x : i0.x, (c & 2) ? i1.y : i0.y, (c & 4) ? i1.z : i0.z);
    double w = ((c & 1) ? t.x : 1 - t.x) * ((c & 2) ? t.y : 1 - t.y) * ((c & 4) ? t.z : 1 - t.z);
    if (w != 0.0) out += w * v.value_at(q.x, q.y, q.z);
  }
  return out;
}

TEST(DicomData, PhilipsSeriesMatchesDcm2niixVoxelsAndWorldPositions) {
  SKIP_WITHOUT_SHARED_DATA("dicom/ct-philips");
  DicomVolume d = read_dicom(shared_data("dicom/ct-philips"));
  VolumeData ref = read_volume(shared_data("dicom/ref/ct-philips.nii.gz"));
  ASSERT_EQ(d.volume.dims, ref.dims);
  EXPECT_EQ(d.series.number, 201);
  EXPECT_EQ(d.series.slices, 28);
  EXPECT_EQ(d.units, "HU");
  EXPECT_EQ(d.volume.type(), VoxelType::i16);  // slope 1, intercept -1024, 12-bit stored
  ASSERT_TRUE(d.window.has_value());
  EXPECT_DOUBLE_EQ(d.window->x, 40.0);
  EXPECT_DOUBLE_EQ(d.window->y, 80.0);
  // Every reference voxel maps to one of ours (whatever flips dcm2niix applies) with the same
  // value, and the same world position within 0.01 mm.
  const glm::dmat4 to_ours = glm::inverse(d.volume.index_to_world);
  double worst_mm = 0.0, worst_index = 0.0;
  size_t mismatches = 0;
  for (int k = 0; k < ref.dims.z; ++k)
    for (int j = 0; j < ref.dims.y; ++j)
      for (int i = 0; i < ref.dims.x; ++i) {
        glm::dvec3 w = world(ref.index_to_world, {i, j, k});
        glm::dvec3 o = world(to_ours, w);
        glm::dvec3 r = glm::round(o);
        worst_index = std::max(worst_index, glm::length(o - r));
        ASSERT_TRUE(r.x >= 0 && r.y >= 0 && r.z >= 0 && r.x < ref.dims.x && r.y < ref.dims.y &&
                    r.z < ref.dims.z);
        worst_mm = std::max(worst_mm, glm::length(world(d.volume.index_to_world, r) - w));
        if (d.volume.value_at(int(r.x), int(r.y), int(r.z)) != ref.value_at(i, j, k)) ++mismatches;
      }
  EXPECT_EQ(mismatches, 0u);
  EXPECT_LT(worst_mm, 0.01);
  EXPECT_LT(worst_index, 0.01);
  // Corners, explicitly: voxel (0,0,0) is the first pixel of the lowest slice (I10).
  EXPECT_LT(
      glm::length(world(d.volume.index_to_world, {0, 0, 0}) - glm::dvec3(-115.5, -1.85, 696.21)),
      0.01);
  EXPECT_LT(glm::length(world(d.volume.index_to_world, {511, 511, 27}) -
                        glm::dvec3(-115.5 + 511 * 0.451171875, -1.85 + 511 * 0.451171875,
                                   696.21 + 27 * 5.0)),
            0.01);
}

TEST(DicomData, DirfileAndSingleFileAndListing) {
  SKIP_WITHOUT_SHARED_DATA("dicom/ct-philips");
  std::vector<DicomSeriesInfo> list = list_dicom_series(shared_data("dicom/ct-philips/DIRFILE"));
  ASSERT_EQ(list.size(), 1u);
  EXPECT_EQ(list[0].id, "201");
  EXPECT_EQ(list[0].description, "STD BRAIN 5MM");
  EXPECT_EQ(list[0].modality, "CT");
  EXPECT_EQ(list[0].rows, 512);
  EXPECT_EQ(list[0].slices, 28);
  EXPECT_EQ(list[0].files.size(), 28u);  // the DIRFILE itself is not an image
  DicomVolume one = read_dicom(shared_data("dicom/ct-philips/I10"));
  EXPECT_EQ(one.volume.dims, glm::ivec3(512, 512, 1));
  EXPECT_TRUE(is_dicom_source(shared_data("dicom/ct-philips")));
  EXPECT_TRUE(is_dicom_source(shared_data("dicom/ct-philips/I10")));
  EXPECT_FALSE(is_dicom_source(shared_data("FLAIR.nrrd")));
}

TEST(DicomData, NineTransferSyntaxesDecodeToIdenticalPixels) {
  SKIP_WITHOUT_SHARED_DATA("dicom/ts");
  DicomVolume first = read_dicom(shared_data("dicom/ts/1.dcm"));
  for (int n = 2; n <= 9; ++n) {
    SCOPED_TRACE(n);
    DicomVolume d = read_dicom(shared_data("dicom/ts/" + std::to_string(n) + ".dcm"));
    ASSERT_EQ(d.volume.dims, first.volume.dims);
    EXPECT_EQ(d.volume.voxels, first.volume.voxels);
    EXPECT_EQ(d.volume.index_to_world, first.volume.index_to_world);
  }
  auto [lo, hi] = first.volume.range();
  EXPECT_LT(lo, hi);  // not a blank image
}

// Mutants of the compressed files (bytes changed at the start of the pixel data, where the
// codec's headers lie): each either loads or is one imx::Error naming the file. Before the
// decoders ran in a process of their own, about 1 in 40 such mutants aborted the whole program.
TEST(DicomData, CompressedMutantsLoadOrFailWithTheirNameNeverCrash) {
  SKIP_WITHOUT_SHARED_DATA("dicom/ts");
  test::TempDir dir;
  std::mt19937 random(2026);
  int refused = 0, loaded = 0, reported_corrupt = 0, decoder_died = 0;
  for (int n = 4; n <= 9; ++n) {
    const std::string bytes =
        test::read_bytes(shared_data("dicom/ts/" + std::to_string(n) + ".dcm"));
    const size_t pixels = bytes.rfind(std::string("\xe0\x7f\x10\x00", 4)) + 12;
    for (int m = 0; m < 40; ++m) {
      std::string mutant = bytes;
      for (int k = 0, count = 1 + static_cast<int>(random() % 8); k < count; ++k)
        mutant[pixels + random() % 400] = static_cast<char>(random() % 256);
      const fs::path file = dir / fmt::format("m{}_{}.dcm", n, m);
      test::write_bytes(file, mutant);
      try {
        read_dicom(file);
        ++loaded;
      } catch (const Error& e) {
        ++refused;
        EXPECT_NE(std::string(e.what()).find(file.string()), std::string::npos) << e.what();
        reported_corrupt += std::string(e.what()).find("corrupt") != std::string::npos;
        decoder_died += std::string(e.what()).find("decoder failed") != std::string::npos;
      }
    }
  }
  std::printf("240 mutants: %d loaded, %d refused (%d as corrupt; the decoder died on %d)\n",
              loaded, refused, reported_corrupt, decoder_died);
  EXPECT_GT(reported_corrupt, 0);
}

TEST(DicomData, EnhancedMultiFrameUsesPerFrameGroups) {
  SKIP_WITHOUT_SHARED_DATA("enh.dcm");
  DicomVolume d = read_dicom(shared_data("enh.dcm"));
  EXPECT_EQ(d.volume.dims, glm::ivec3(64, 64, 6));
  EXPECT_EQ(d.series.modality, "MR");
  glm::dvec3 s = d.volume.spacing();
  EXPECT_NEAR(s.x, 3.375, 1e-9);
  EXPECT_NEAR(s.y, 3.375, 1e-9);
  EXPECT_NEAR(s.z, 2.4, 1e-3);
  // PlanePositionSequence of frames 1 and 6.
  EXPECT_LT(glm::length(world(d.volume.index_to_world, {0, 0, 0}) -
                        glm::dvec3(-109.79, -58.4773, -5.40356)),
            0.01);
  EXPECT_LT(glm::length(world(d.volume.index_to_world, {0, 0, 5}) -
                        glm::dvec3(-109.79, -58.4774, 6.59644)),
            0.01);
  ASSERT_TRUE(d.window.has_value());  // FrameVOILUTSequence
  EXPECT_DOUBLE_EQ(d.window->x, 621.0);
}

TEST(DicomData, GeTiltAcquiredSlicesLieWhereTheTagsSay) {
  SKIP_WITHOUT_SHARED_DATA("dicom/ct-ge-tilt");
  detail::AcquiredSeries a =
      std::move(detail::read_acquired_volumes(shared_data("dicom/ct-ge-tilt"), "", {0}).front());
  ASSERT_EQ(a.stack.frames.size(), 28u);
  DicomVolume d = read_dicom(shared_data("dicom/ct-ge-tilt"));
  // Before resampling: voxel (i, j) of slice s at IPP_s + i dcol row + j drow column.
  const glm::dvec3 row(1, 0, 0), col(0, 0.9483237, -0.3173047);
  const double dc = 0.4882812, dr = 0.4882812;
  const glm::dvec3 ipp0(-125.0, -123.5404569, 5.8360586);
  ASSERT_LT(glm::length(*a.stack.frames[0].position - ipp0), 1e-6);
  // The resampled grid's slice k lies on the line of IPPs; at an acquired slice's position the
  // resampled volume holds that slice.
  const glm::dmat4 to_index = glm::inverse(d.volume.index_to_world);
  size_t on_grid = 0;
  for (size_t s = 0; s < a.stack.frames.size(); ++s) {
    const glm::dvec3 ipp = *a.stack.frames[s].position;
    for (glm::ivec2 ij : {glm::ivec2(0, 0), glm::ivec2(511, 0), glm::ivec2(0, 511),
                          glm::ivec2(511, 511), glm::ivec2(200, 300)}) {
      glm::dvec3 expected = ipp + ij.x * dc * row + ij.y * dr * col;
      glm::dvec3 idx = world(to_index, expected);
      // In-plane indices are exactly i and j: the shear keeps rows and columns in place.
      EXPECT_NEAR(idx.x, ij.x, 1e-4);  // the tags' directions are unit to 7 decimals
      EXPECT_NEAR(idx.y, ij.y, 1e-4);
      // The world position of (i, j, k) for fractional k reproduces the tag geometry.
      EXPECT_LT(glm::length(world(d.volume.index_to_world, idx) - expected), 0.01);
    }
    // Along k: the value at the slice's position is the blend of the two grid slices around it,
    // each a blend of acquired slices; on a grid point it is the acquired slice itself.
    double k = world(to_index, ipp).z;
    if (std::abs(k - std::round(k)) < 1e-6) {
      ++on_grid;
      int kk = int(std::round(k));
      for (int p : {0, 1000, 131072, 262143})
        EXPECT_NEAR(d.volume.value_at(p % 512, p / 512, kk), a.values[s][size_t(p)], 1e-3);
    }
  }
  EXPECT_GE(on_grid, 2u);  // at least the first and the last
  // Between grid points: each resampled slice is the linear blend of its acquired neighbours.
  std::vector<double> along;
  for (const auto& f : a.stack.frames) along.push_back(glm::length(*f.position - ipp0));
  for (int k = 0; k < d.volume.dims.z; k += 7) {
    double x = glm::length(world(d.volume.index_to_world, {0, 0, k}) - ipp0);
    size_t s = std::upper_bound(along.begin(), along.end(), x + 1e-9) - along.begin();
    s = std::clamp<size_t>(s, 1, along.size() - 1) - 1;
    double w = (x - along[s]) / (along[s + 1] - along[s]);
    for (int p : {5000, 130000, 200000}) {
      double expected = (1 - w) * a.values[s][size_t(p)] + w * a.values[s + 1][size_t(p)];
      EXPECT_NEAR(d.volume.value_at(p % 512, p / 512, k), expected, 1e-2) << "k " << k;
    }
  }
  bool noted = false;
  for (const std::string& n : d.notes) noted |= n.find("1.14 to 7.38 mm") != std::string::npos;
  EXPECT_TRUE(noted);
  EXPECT_LE(d.volume.spacing().z, 1.14 + 1e-6);
}

TEST(DicomData, GeTiltSlicesEqualDcm2niixSlices) {
  SKIP_WITHOUT_SHARED_DATA("dicom/ref/ct-ge-tilt.nii.gz");
  detail::AcquiredSeries a =
      std::move(detail::read_acquired_volumes(shared_data("dicom/ct-ge-tilt"), "", {0}).front());
  VolumeData ref = read_volume(shared_data("dicom/ref/ct-ge-tilt.nii.gz"));
  ASSERT_EQ(ref.dims, glm::ivec3(512, 512, 28));
  // dcm2niix stores rows bottom-up (j flipped) and the slices in our order.
  size_t mismatches = 0;
  for (int k = 0; k < 28; ++k)
    for (int j = 0; j < 512; ++j)
      for (int i = 0; i < 512; ++i)
        if (a.values[size_t(k)][size_t(j) * 512 + size_t(i)] != ref.value_at(i, 511 - j, k))
          ++mismatches;
  EXPECT_EQ(mismatches, 0u);
}

TEST(DicomData, GeTiltMatchesDcm2niixTiltCorrectedVolume) {
  SKIP_WITHOUT_SHARED_DATA("dicom/ref/ct-ge-tilt_corrected_equidistant.nii.gz");
  DicomVolume d = read_dicom(shared_data("dicom/ct-ge-tilt"));
  VolumeData ref = read_volume(shared_data("dicom/ref/ct-ge-tilt_corrected_equidistant.nii.gz"));
  // Normalized cross-correlation over an axial and a sagittal MPR plane through the middle of
  // our volume, sampled at 1 mm in world space where both volumes have data inside the scan's
  // field of view (GDCM's padding value -1500 elsewhere).
  const glm::dmat4 ours_inv = glm::inverse(d.volume.index_to_world);
  const glm::dmat4 ref_inv = glm::inverse(ref.index_to_world);
  const glm::dvec3 centre = world(d.volume.index_to_world, glm::dvec3(d.volume.dims - 1) * 0.5);
  auto ncc_at = [&](glm::dvec3 shift, int stride, std::vector<double>& xs,
                    std::vector<double>& ys) {
    xs.clear();
    ys.clear();
    for (int plane = 0; plane < 2; ++plane)
      for (int u = -120; u <= 120; u += stride)
        for (int v = -80; v <= 80; v += stride) {
          glm::dvec3 p = plane == 0 ? centre + glm::dvec3(u, v, 0) : centre + glm::dvec3(0, u, v);
          auto a = sample(d.volume, world(ours_inv, p));
          auto b = sample(ref, world(ref_inv, p + shift));
          if (!a || !b || *a < -1400 || *b < -1400) continue;
          xs.push_back(*a);
          ys.push_back(*b);
        }
    double mx = 0, my = 0;
    for (size_t i = 0; i < xs.size(); ++i) mx += xs[i], my += ys[i];
    mx /= xs.size();
    my /= ys.size();
    double sxy = 0, sxx = 0, syy = 0;
    for (size_t i = 0; i < xs.size(); ++i) {
      sxy += (xs[i] - mx) * (ys[i] - my);
      sxx += (xs[i] - mx) * (xs[i] - mx);
      syy += (ys[i] - my) * (ys[i] - my);
    }
    return sxy / std::sqrt(sxx * syy);
  };
  std::vector<double> xs, ys;
  const double at_zero = ncc_at(glm::dvec3(0.0), 1, xs, ys);
  ASSERT_GT(xs.size(), 20000u);
  // dcm2niix's tilt correction moves the volume: find the shift (a 5 mm grid) that fits best.
  double best = -1.0;
  glm::dvec3 best_shift(0.0);
  for (int dz = -45; dz <= 5; dz += 5)
    for (int dy = -10; dy <= 30; dy += 5)
      if (double c = ncc_at(glm::dvec3(0, dy, dz), 3, xs, ys); c > best) {
        best = c;
        best_shift = glm::dvec3(0, dy, dz);
      }
  std::printf(
      "GE tilt vs dcm2niix tilt-corrected: NCC %.3f in place, %.3f after moving it by "
      "(%g, %g, %g) mm\n",
      at_zero, best, best_shift.x, best_shift.y, best_shift.z);
  EXPECT_GT(at_zero, 0.4);
  EXPECT_GT(best, 0.8);
}
}  // namespace
}  // namespace imx
