// A gantry-tilted CT is a sheared index-to-world affine (issue 18): the renderer must place,
// shade (gradients), skip (bricks), clip and slice (MPR planes) it as it does a regular grid.
// The same analytic field sampled on a regular and on a sheared grid must render alike.
#include <gtest/gtest.h>

#include <cmath>
#include <memory>
#include <string>

#include <glm/glm.hpp>
#include <glm/gtc/matrix_transform.hpp>

#include "core/math.hpp"
#include "intermix/metrics.hpp"
#include "intermix/render.hpp"
#include "intermix/scene.hpp"

namespace imx {
namespace {

// A bone-like shell (value 1000 between radii 14 and 20 mm) around a soft core (300),
// off-centre so that a misplaced grid shows, with smooth edges to keep interpolation honest.
double field(const glm::dvec3& p) {
  const double r = glm::length(p - glm::dvec3(3.0, -2.0, 1.0));
  auto step = [](double x) { return 0.5 + 0.5 * std::tanh(x / 1.2); };
  return 300.0 * step(14.0 - r) + 1000.0 * step(r - 14.0) * step(20.0 - r);
}

// 72 x 72 x 56 voxels of 0.75 x 0.75 x 1 mm around the origin; `tilt_deg` tilts the slice
// axis towards +y the way a CT gantry does, keeping slices in planes of constant z.
std::shared_ptr<VolumeData> sampled(double tilt_deg) {
  auto v = std::make_shared<VolumeData>();
  v->dims = {72, 72, 56};
  glm::dmat4 m(1.0);
  m[0] = {0.75, 0.0, 0.0, 0.0};
  m[1] = {0.0, 0.75, 0.0, 0.0};
  m[2] = {0.0, std::tan(glm::radians(tilt_deg)), 1.0, 0.0};
  m[3] = {-0.75 * 35.5, -0.75 * 35.5 - 27.5 * m[2].y, -27.5, 1.0};
  v->index_to_world = m;
  std::vector<float> voxels(static_cast<size_t>(72) * 72 * 56);
  size_t n = 0;
  for (int k = 0; k < 56; ++k)
    for (int j = 0; j < 72; ++j)
      for (int i = 0; i < 72; ++i)
        voxels[n++] = static_cast<float>(field(transform_point(m, glm::dvec3(i, j, k))));
  v->voxels = std::move(voxels);
  return v;
}

Scene scene_of(std::shared_ptr<VolumeData> data) {
  Scene scene;
  scene.camera.eye = {-160.0, -260.0, 120.0};
  scene.camera.target = {0.0, 0.0, 0.0};
  scene.camera.fov_deg = 18.0;
  scene.image.width = 96;
  scene.image.height = 96;
  VolumeObject v;
  v.name = "ct";
  v.index_to_world = data->index_to_world;
  v.data = std::move(data);
  v.transfer_function.points = {{150.0, {0.8f, 0.5f, 0.4f, 0.0f}},
                                {300.0, {0.8f, 0.5f, 0.4f, 0.04f}},
                                {700.0, {1.0f, 1.0f, 0.9f, 0.5f}},
                                {1000.0, {1.0f, 1.0f, 0.95f, 0.9f}}};
  v.shading.enabled = true;
  // Cut away the front: the shaded cut and the core behind it need the grid to be right.
  v.clip_planes.push_back({{0.0, 0.0, 4.0}, glm::normalize(glm::dvec3(0.3, 0.2, -1.0))});
  scene.volumes.push_back(std::move(v));
  scene.order.push_back({ObjectKind::volume, 0});
  PlaneObject mpr;  // an axial slice through the volume, beside the cut
  mpr.name = "axial";
  mpr.volume = 0;
  mpr.center = {0.0, 0.0, -6.0};
  mpr.normal = {0.0, 0.0, 1.0};
  mpr.size = {30.0, 30.0};  // inside both grids: their extents differ
  mpr.window = {500.0, 1200.0};
  scene.planes.push_back(mpr);
  scene.order.push_back({ObjectKind::plane, 0});
  return scene;
}

class ShearedVolume : public testing::TestWithParam<std::string> {};

TEST_P(ShearedVolume, RendersLikeTheSameFieldOnARegularGrid) {
  RenderOptions options;
  options.method = GetParam();
  const Image regular = render(scene_of(sampled(0.0)), options);
  const Image tilted = render(scene_of(sampled(25.0)), options);
  // A wrong gradient transform, a brick missed or a plane sampled in the wrong place costs
  // far more than the two grids' interpolation differences.
  const double db = psnr(regular, tilted);
  RecordProperty("psnr_db", std::to_string(db));
  EXPECT_GT(db, 45.0) << GetParam();  // measured 52.3 (mdvr) to 54.0 dB (reference)
  // And the tilt must matter: the same voxels placed without it are far off.
  auto untilted = sampled(25.0);
  untilted->index_to_world = sampled(0.0)->index_to_world;
  EXPECT_LT(psnr(regular, render(scene_of(untilted), options)), db - 10.0) << GetParam();
}

INSTANTIATE_TEST_SUITE_P(Methods, ShearedVolume,
                         testing::Values("mdvr", "zslab-hybrid", "dfb", "reference"));

}  // namespace
}  // namespace imx
