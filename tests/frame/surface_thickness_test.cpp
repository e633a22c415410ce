#include <gtest/gtest.h>

#include "frame/surface_thickness.hpp"

namespace imx {
namespace {

Scene two_meshes() {
  Scene s;
  s.image.width = s.image.height = 100;
  s.meshes.resize(2);
  s.planes.resize(1);
  s.order = {{ObjectKind::mesh, 0}, {ObjectKind::plane, 0}, {ObjectKind::mesh, 1}};
  return s;
}

TEST(SurfaceThickness, AutoIsAPixelFootprintOrTwiceTheFloatQuantum) {
  Scene s = two_meshes();
  CameraModel camera(s.camera, 100, 100);
  SurfaceThickness th(s, camera);
  for (float t : {1.0f, 100.0f, 600.0f}) {
    float expected = std::max(float(camera.pixel_footprint(t)), 2.0f * t / 8388608.0f);
    EXPECT_NEAR(th.of(0, t), expected, 1e-6f * expected);
  }
  s.camera.projection = Projection::orthographic;  // constant footprint; the quantum wins far away
  CameraModel ortho(s.camera, 100, 100);
  SurfaceThickness to(s, ortho);
  EXPECT_NEAR(to.of(0, 10.0f), ortho.pixel_footprint(10.0), 1e-6);
  EXPECT_NEAR(to.of(0, 1e8f), 2e8f / 8388608.0f, 1e-3);
}

TEST(SurfaceThickness, ObjectValueOverridesTheGlobalDefault) {
  Scene s = two_meshes();
  s.render.thickness = 2.0;
  s.meshes[1].thickness = 0.5;
  s.planes[0].thickness = 0.0;
  CameraModel camera(s.camera, 100, 100);
  SurfaceThickness th(s, camera);
  EXPECT_EQ(th.of(0, 50.0f), 2.0f);
  EXPECT_EQ(th.of(1, 50.0f), 0.0f);
  EXPECT_EQ(th.of(2, 50.0f), 0.5f);
  Slab slab = th.slab(Fragment{50.0f, glm::vec4(0.5f), 2, 1});
  EXPECT_EQ(slab.t_back, 50.0f);
  EXPECT_EQ(slab.front(), 49.5f);
  SurfaceThickness zero(s, camera, true);
  EXPECT_EQ(zero.of(0, 50.0f), 0.0f);
  EXPECT_EQ(zero.of(2, 50.0f), 0.0f);
}

}  // namespace
}  // namespace imx
