// Thick slabs and oblique reading views: a slab's MIP, MinIP and mean are the max, min and mean
// of the voxels across it; a tilted grid's slab is sampled in world space along the view's
// normal; an oblique view's pixel is the trilinear sample at its world point.
#include <algorithm>
#include <cmath>

#include <gtest/gtest.h>
#include <glm/gtc/matrix_transform.hpp>

#include "core/colour.hpp"
#include "core/math.hpp"
#include "frame/slice_view.hpp"

namespace imx {
namespace {

constexpr glm::ivec3 kDims{8, 8, 16};

// Voxel values in [0, 1000) that vary without order (a slab's max is not at its edge).
float value_of(int i, int j, int k) {
  return static_cast<float>((i * 73 + j * 151 + k * 337 + i * j * k * 17) % 997);
}

Scene scene_of(const glm::dmat4& index_to_world, bool ramp = false) {
  VolumeData d;
  d.dims = kDims;
  std::vector<float> values(static_cast<size_t>(kDims.x * kDims.y * kDims.z));
  for (int k = 0; k < kDims.z; ++k)
    for (int j = 0; j < kDims.y; ++j)
      for (int i = 0; i < kDims.x; ++i)
        values[static_cast<size_t>(i + kDims.x * (j + kDims.y * k))] =
            ramp ? static_cast<float>(i + 10 * j + 50 * k) : value_of(i, j, k);
  d.voxels = std::move(values);
  Scene s;
  VolumeObject v;
  v.name = "v";
  v.data = std::make_shared<const VolumeData>(std::move(d));
  v.index_to_world = index_to_world;
  v.transfer_function.points = {{0.0, glm::vec4(0.0f)}, {1000.0, glm::vec4(1.0f)}};
  s.volumes.push_back(v);
  s.order.push_back({ObjectKind::volume, 0});
  return s;
}

// A pixel's value through the window [0, 1000] (its display grey * 1000).
double shown(const Image& image, int x, int y) {
  return srgb_encode(image.at(x, y).r) * 1000.0;
}

const std::vector<glm::dvec2> kWindow = {{500.0, 1000.0}};

TEST(ThickSlab, MipMinipAndMeanAreThoseOfTheVoxelsAcrossTheSlab) {
  const Scene s = scene_of(glm::dmat4(1.0));
  // Axial through voxel layer 7, 5 mm thick: layers 5 to 9, one sample on each voxel centre.
  for (SlabMode mode : {SlabMode::mip, SlabMode::minip, SlabMode::mean}) {
    SliceView view = slice_view(SliceAxis::axial, {3.5, 3.5, 7.0}, 8, 8, 1.0);
    view.slab = {5.0, mode};
    const Image image = render_slice(s, view, {0}, kWindow);
    for (int y = 0; y < 8; ++y)
      for (int x = 0; x < 8; ++x) {
        float lo = 1e9f, hi = -1e9f;
        double sum = 0.0;
        for (int k = 5; k <= 9; ++k) {
          lo = std::min(lo, value_of(x, y, k));
          hi = std::max(hi, value_of(x, y, k));
          sum += value_of(x, y, k);
        }
        const double want = mode == SlabMode::mip ? hi : mode == SlabMode::minip ? lo : sum / 5;
        ASSERT_NEAR(shown(image, x, y), want, 2e-3)
            << slab_mode_name(mode) << " " << x << ", " << y;
      }
  }
  // Coronal through y = 4, 3 mm thick: rows 3 to 5 along the view's normal (+y).
  SliceView coronal = slice_view(SliceAxis::coronal, {3.5, 4.0, 7.5}, 8, 16, 1.0);
  coronal.slab = {3.0, SlabMode::mip};
  const Image c = render_slice(s, coronal, {0}, kWindow);
  for (int y = 0; y < 16; ++y)
    for (int x = 0; x < 8; ++x) {
      const int k = 15 - y;  // down is inferior
      const float want = std::max({value_of(x, 3, k), value_of(x, 4, k), value_of(x, 5, k)});
      ASSERT_NEAR(shown(c, x, y), want, 2e-3) << x << ", " << y;
    }
  // A thin slab (below the pitch) is the plane alone.
  SliceView thin = slice_view(SliceAxis::axial, {3.5, 3.5, 7.0}, 8, 8, 1.0);
  thin.slab = {0.5, SlabMode::mip};
  EXPECT_NEAR(shown(render_slice(s, thin, {0}, kWindow), 2, 3), value_of(2, 3, 7), 2e-3);
}

TEST(ThickSlab, SamplingFollowsThePitchAndIsBounded) {
  EXPECT_EQ(slab_sampling(0.0, 1.0).count, 1);
  EXPECT_EQ(slab_sampling(5.0, 1.0).count, 5);
  EXPECT_DOUBLE_EQ(slab_sampling(5.0, 1.0).spacing, 1.0);
  EXPECT_EQ(slab_sampling(5.0, 0.7).count, 8);  // never further apart than the pitch
  EXPECT_LE(slab_sampling(5.0, 0.7).spacing, 0.7);
  EXPECT_EQ(slab_sampling(1000.0, 0.01).count, kMaxSlabSamples);
  EXPECT_EQ(slab_sampling(std::nan(""), 1.0).count, 1);
}

// A tilted, anisotropic grid: the slab's samples lie along the view's normal in world space,
// at most the grid's pitch along it apart, and the MIP is the largest trilinear sample among
// them.
TEST(ThickSlab, ATiltedGridIsSampledAlongTheViewsNormalInWorldSpace) {
  glm::dmat4 m = glm::rotate(glm::dmat4(1.0), glm::radians(25.0), glm::dvec3(1.0, 0.3, 0.2));
  m = glm::scale(m, glm::dvec3(0.9, 1.1, 0.8));
  const Scene s = scene_of(m);
  SliceView view =
      slice_view(SliceAxis::axial, transform_point(m, glm::dvec3(3.5, 3.5, 7.5)), 10, 10, 0.6);
  view.slab = {4.0, SlabMode::mip};
  const Image image = render_slice(s, view, {0}, kWindow);
  // The pitch along the normal (+z): the mm of one voxel step along it in index space.
  const double pitch = 1.0 / glm::length(glm::inverse(glm::dmat3(m)) * glm::dvec3(0, 0, 1));
  const SlabSampling sampling = slab_sampling(4.0, pitch);
  ASSERT_GE(sampling.count, 4);
  ASSERT_LE(sampling.spacing, pitch);
  int checked = 0;
  for (int y = 0; y < 10; ++y)
    for (int x = 0; x < 10; ++x) {
      double best = -1.0;
      bool all_inside = true;
      for (int k = 0; k < sampling.count; ++k) {
        const double t = (k - 0.5 * (sampling.count - 1)) * sampling.spacing;
        const glm::dvec3 p = view.world(x + 0.5, y + 0.5) + t * glm::dvec3(0, 0, 1);
        const std::optional<double> v = sample_at(s.volumes[0], p);
        if (!v) all_inside = false;
        if (v) best = std::max(best, *v);
      }
      if (!all_inside) continue;
      ASSERT_NEAR(shown(image, x, y), best, 0.05) << x << ", " << y;
      ++checked;
    }
  EXPECT_GT(checked, 40);
}

// An oblique view: its frame is orthonormal, its normal the rotated axis's, its up as near the
// patient's as it can be; each pixel is the trilinear sample at its world point, which on a
// linear ramp is the ramp's value there.
TEST(ObliqueView, APixelIsTheTrilinearSampleAtItsWorldPoint) {
  const glm::dmat3 r =
      glm::dmat3(glm::rotate(glm::dmat4(1.0), glm::radians(30.0), glm::dvec3(0, 0, 1))) *
      glm::dmat3(glm::rotate(glm::dmat4(1.0), glm::radians(20.0), glm::dvec3(1, 0, 0)));
  const Scene s = scene_of(glm::scale(glm::dmat4(1.0), glm::dvec3(1.0, 1.0, 0.5)), true);
  const glm::dvec3 centre(3.5, 3.5, 3.75);
  for (SliceAxis axis : {SliceAxis::axial, SliceAxis::coronal, SliceAxis::sagittal}) {
    const SliceView flat = slice_view(axis, centre, 12, 12, 0.5);
    const SliceView v = slice_view(axis, centre, 12, 12, 0.5, r);
    EXPECT_NEAR(glm::length(v.normal - r * flat.normal), 0.0, 1e-12);
    EXPECT_NEAR(glm::dot(v.right, v.down), 0.0, 1e-12);
    EXPECT_NEAR(glm::dot(v.right, v.normal), 0.0, 1e-12);
    EXPECT_NEAR(glm::length(v.right), 0.5, 1e-12);
    // The same handedness as the axis's own view (the sagittal view's is mirrored).
    EXPECT_GT(glm::dot(glm::cross(v.right, v.down), v.normal) *
                  glm::dot(glm::cross(flat.right, flat.down), flat.normal),
              0.0);
    // Down stays in the plane of the axis's down and the normal: no roll.
    EXPECT_NEAR(glm::dot(glm::cross(flat.down, v.normal), v.down), 0.0, 1e-12);
    const Image image = render_slice(s, v, {0}, kWindow);
    int checked = 0;
    for (int y = 0; y < 12; ++y)
      for (int x = 0; x < 12; ++x) {
        const glm::dvec3 p = v.world(x + 0.5, y + 0.5);
        const glm::dvec3 index(p.x, p.y, p.z / 0.5);
        if (glm::any(glm::lessThan(index, glm::dvec3(0.0))) ||
            glm::any(glm::greaterThan(index, glm::dvec3(kDims - 1))))
          continue;
        const double ramp = index.x + 10 * index.y + 50 * index.z;
        ASSERT_NEAR(*sample_at(s.volumes[0], p), ramp, 1e-9);
        ASSERT_NEAR(shown(image, x, y), ramp, 0.05)
            << slice_axis_name(axis) << " " << x << ", " << y;
        ++checked;
      }
    EXPECT_GT(checked, 20) << slice_axis_name(axis);
  }
}

// A view turned to face along its own down (the axial view turned 90 degrees about L): its down
// turns with it, and the frame stays orthonormal with the axis's handedness.
TEST(ObliqueView, AViewFacingAlongItsDownTakesTheRotatedDown) {
  const glm::dmat3 r =
      glm::dmat3(glm::rotate(glm::dmat4(1.0), glm::radians(90.0), glm::dvec3(1, 0, 0)));
  for (SliceAxis axis : {SliceAxis::axial, SliceAxis::coronal, SliceAxis::sagittal}) {
    const SliceView flat = slice_view(axis, glm::dvec3(0.0), 4, 4, 1.0);
    const SliceView v = slice_view(axis, glm::dvec3(0.0), 4, 4, 1.0, r);
    EXPECT_NEAR(glm::length(v.normal - r * flat.normal), 0.0, 1e-12) << slice_axis_name(axis);
    EXPECT_NEAR(glm::length(v.down), 1.0, 1e-12) << slice_axis_name(axis);
    EXPECT_NEAR(glm::dot(v.down, v.normal), 0.0, 1e-12) << slice_axis_name(axis);
    EXPECT_NEAR(glm::dot(v.right, v.down), 0.0, 1e-12) << slice_axis_name(axis);
    EXPECT_GT(glm::dot(glm::cross(v.right, v.down), v.normal) *
                  glm::dot(glm::cross(flat.right, flat.down), flat.normal),
              0.0)
        << slice_axis_name(axis);
  }
  // The axial view, its normal S turned to A, takes its down (P) turned: S.
  const SliceView axial = slice_view(SliceAxis::axial, glm::dvec3(0.0), 4, 4, 1.0, r);
  EXPECT_NEAR(glm::length(axial.down - r * glm::dvec3(0, 1, 0)), 0.0, 1e-12);
}

}  // namespace
}  // namespace imx
