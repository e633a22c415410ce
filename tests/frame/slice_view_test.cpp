// The 2-D reading views: each axis shows the patient as radiologists read it, pixels sample the
// voxels they lie on, the base volume is windowed grey, overlays colour it, meshes outline.
#include "frame/slice_view.hpp"
#include "core/colour.hpp"
#include "intermix/error.hpp"

#include <cmath>
#include <limits>

#include <gtest/gtest.h>

namespace imx {
namespace {

// 8^3 voxels of value i + 10 j + 100 k, voxel (i, j, k) at world (i, j, k) mm (LPS).
std::shared_ptr<const VolumeData> ramp(bool nan_first = false) {
  VolumeData v;
  v.dims = {8, 8, 8};
  std::vector<float> values(512);
  for (int k = 0; k < 8; ++k)
    for (int j = 0; j < 8; ++j)
      for (int i = 0; i < 8; ++i)
        values[static_cast<size_t>(i + 8 * j + 64 * k)] = i + 10 * j + 100 * k;
  if (nan_first) values[0] = std::numeric_limits<float>::quiet_NaN();
  v.voxels = std::move(values);
  return std::make_shared<const VolumeData>(std::move(v));
}

Scene ramp_scene() {
  Scene s;
  VolumeObject v;
  v.name = "ramp";
  v.data = ramp();
  v.transfer_function.points = {{0.0, glm::vec4(0.0f)}, {800.0, glm::vec4(1.0f, 0.0f, 0.0f, 1.0f)}};
  s.volumes.push_back(v);
  s.order.push_back({ObjectKind::volume, 0});
  return s;
}

// The value a pixel shows through the window [0, 1000]: its display grey * 1000 (the view is
// linear like a render, the window's grey a display grey: docs/colour.md).
double shown_value(const Image& image, int x, int y) {
  return srgb_encode(image.at(x, y).r) * 1000.0;
}

TEST(SliceView, EachAxisShowsThePatientAsRadiologistsReadIt) {
  const Scene s = ramp_scene();
  const std::vector<glm::dvec2> window = {{500.0, 1000.0}};
  // Axial through z = 3: x to the right is patient left (+x), down is posterior (+y).
  const SliceView axial = slice_view(SliceAxis::axial, {3.5, 3.5, 3.0}, 8, 8, 1.0);
  const Image a = render_slice(s, axial, {0}, window);
  for (int y = 0; y < 8; ++y)
    for (int x = 0; x < 8; ++x) ASSERT_NEAR(shown_value(a, x, y), x + 10 * y + 300, 1e-3);
  // Coronal through y = 3: right is +x, down is inferior (-z).
  const Image c =
      render_slice(s, slice_view(SliceAxis::coronal, {3.5, 3.0, 3.5}, 8, 8, 1.0), {0}, window);
  for (int y = 0; y < 8; ++y)
    for (int x = 0; x < 8; ++x) ASSERT_NEAR(shown_value(c, x, y), x + 30 + 100 * (7 - y), 1e-3);
  // Sagittal through x = 3: right is posterior (+y), anterior on the left; down is inferior.
  const Image g =
      render_slice(s, slice_view(SliceAxis::sagittal, {3.0, 3.5, 3.5}, 8, 8, 1.0), {0}, window);
  for (int y = 0; y < 8; ++y)
    for (int x = 0; x < 8; ++x) ASSERT_NEAR(shown_value(g, x, y), 3 + 10 * x + 100 * (7 - y), 1e-3);
  // A pixel maps back to where it samples.
  const glm::dvec2 p = axial.pixel({5.0, 2.0, 3.0});
  EXPECT_NEAR(p.x, 5.5, 1e-12);
  EXPECT_NEAR(p.y, 2.5, 1e-12);
}

TEST(SliceView, OutsideTheGridAndNoDataShowNothing) {
  Scene s = ramp_scene();
  s.volumes[0].data = ramp(true);
  // Pixels of 2 mm around (0, 0, 0): the first lies on the NaN voxel, the last outside.
  const Image a =
      render_slice(s, slice_view(SliceAxis::axial, {0.0, 0.0, 0.0}, 2, 2, 2.0), {0}, {{500, 1000}});
  EXPECT_EQ(a.at(0, 0).a, 0.0f);  // (-1, -1, 0): outside
  EXPECT_EQ(a.at(1, 1).a, 1.0f);  // (1, 1, 0)
  const Image nan =
      render_slice(s, slice_view(SliceAxis::axial, {0.0, 0.0, 0.0}, 1, 1, 0.5), {0}, {{500, 1000}});
  EXPECT_EQ(nan.at(0, 0).a, 0.0f);
}

TEST(SliceView, AnOverlayVolumeColoursTheBaseByItsTransferFunction) {
  Scene s = ramp_scene();
  VolumeObject hot = s.volumes[0];
  hot.name = "hot";
  s.volumes.push_back(hot);
  const std::vector<glm::dvec2> windows = {{500.0, 1000.0}, {0.0, 1.0}};
  const SliceView v = slice_view(SliceAxis::axial, {3.5, 3.5, 7.0}, 8, 8, 1.0);
  const Image base = render_slice(s, v, {0}, windows);
  const Image both = render_slice(s, v, {0, 1}, windows);
  // At value 777 the overlay's TF is red with alpha 0.97: mostly red over the grey.
  EXPECT_GT(both.at(7, 7).r, base.at(7, 7).r);
  EXPECT_LT(both.at(7, 7).g, base.at(7, 7).g * 0.5f);
  EXPECT_THROW(render_slice(s, slice_view(SliceAxis::axial, {}, 5000, 1, 1.0), {0}, windows),
               Error);
}

TEST(SliceView, MeshesCrossingThePlaneGiveOutlinesAndProbesReadTheVoxel) {
  Mesh tetra;
  tetra.positions = {{0, 0, 0}, {4, 0, 0}, {0, 4, 0}, {0, 0, 4}};
  tetra.triangles = {{0, 2, 1}, {0, 1, 3}, {0, 3, 2}, {1, 2, 3}};
  const SliceView v = slice_view(SliceAxis::axial, {2.0, 2.0, 1.0}, 16, 16, 0.5);
  const std::vector<glm::dvec4> cut = mesh_outline(tetra, v);
  EXPECT_EQ(cut.size(), 3u);  // the plane z = 1 cuts the three side faces
  for (const glm::dvec4& s : cut) {
    const glm::dvec3 a = v.world(s.x, s.y), b = v.world(s.z, s.w);
    EXPECT_NEAR(a.z, 1.0, 1e-9);
    EXPECT_NEAR(b.z, 1.0, 1e-9);
    EXPECT_LE(a.x + a.y, 3.0 + 1e-9);  // on the face x + y + z = 4 or inside it
  }
  EXPECT_TRUE(mesh_outline(tetra, slice_view(SliceAxis::axial, {0, 0, 9.0}, 16, 16, 0.5)).empty());

  const Scene s = ramp_scene();
  const std::optional<VoxelValue> at = voxel_at(s.volumes[0], {2.4, 5.6, 1.2});
  ASSERT_TRUE(at);
  EXPECT_EQ(at->index, glm::ivec3(2, 6, 1));
  EXPECT_EQ(at->value, 2 + 60 + 100);
  EXPECT_FALSE(voxel_at(s.volumes[0], {-0.6, 0, 0}));
  EXPECT_FALSE(voxel_at(s.volumes[0], {0, 7.6, 0}));
}

}  // namespace
}  // namespace imx
