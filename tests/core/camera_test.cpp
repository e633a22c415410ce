#include <gtest/gtest.h>

#include "core/camera_model.hpp"
#include "intermix/error.hpp"

namespace imx {
namespace {

TEST(CameraModel, PerspectiveProjectsKnownPointsToKnownPixels) {
  Camera cam;  // eye (0,-600,0) looking at the origin, z up, fov 30
  CameraModel m(cam, 512, 256);
  glm::dvec2 c = m.project({0, 0, 0});
  EXPECT_NEAR(c.x, 256.0, 1e-9);
  EXPECT_NEAR(c.y, 128.0, 1e-9);
  // A point at the top edge of the view at the target's depth.
  double top = 600.0 * std::tan(glm::radians(15.0));
  EXPECT_NEAR(m.project({0, 0, top}).y, 0.0, 1e-9);
  // x grows to the right (+x world is right when looking along +y with z up), y grows down.
  glm::dvec2 p = m.project({10, 0, -10});
  EXPECT_GT(p.x, 256.0);
  EXPECT_GT(p.y, 128.0);
  EXPECT_NEAR(p.x - 256.0, 10.0 / top * 128.0, 1e-9);
}

TEST(CameraModel, RaysPassThroughTheirPixelsAndDepthIsDistance) {
  Camera cam;
  CameraModel m(cam, 300, 200);
  for (glm::dvec2 px : {glm::dvec2(10.5, 20.25), glm::dvec2(150, 100), glm::dvec2(299, 1)}) {
    Ray r = m.ray(px.x, px.y);
    EXPECT_NEAR(glm::length(r.dir), 1.0f, 1e-6f);
    glm::dvec3 world = glm::dvec3(r.at(450.0f));
    glm::dvec2 back = m.project(world);
    EXPECT_NEAR(back.x, px.x, 1e-3);
    EXPECT_NEAR(back.y, px.y, 1e-3);
    EXPECT_NEAR(m.depth_of(m.to_camera(world)), 450.0, 1e-3);
  }
}

TEST(CameraModel, OrthographicRaysAreParallelAndDepthIsFromTheEyePlane) {
  Camera cam;
  cam.projection = Projection::orthographic;
  cam.ortho_height = 100;
  CameraModel m(cam, 200, 200);
  Ray a = m.ray(0, 0), b = m.ray(200, 200);
  EXPECT_NEAR(glm::dot(a.dir, b.dir), 1.0f, 1e-7f);
  EXPECT_NEAR(a.origin.x, -50.0f, 1e-4f);
  EXPECT_NEAR(a.origin.z, 50.0f, 1e-4f);
  glm::dvec2 p = m.project({25, 123, -25});
  EXPECT_NEAR(p.x, 150.0, 1e-9);
  EXPECT_NEAR(p.y, 150.0, 1e-9);
  EXPECT_NEAR(m.depth_of(m.to_camera({25, 123, -25})), 723.0, 1e-9);
}

TEST(CameraModel, RejectsDegenerateCameras) {
  Camera cam;
  cam.up = {0, 1, 0};  // parallel to the view
  EXPECT_THROW(CameraModel(cam, 10, 10), Error);
  EXPECT_THROW(CameraModel(Camera{}, 0, 10), Error);
  cam = Camera{};
  cam.eye.x = NAN;
  EXPECT_THROW(CameraModel(cam, 10, 10), Error);
}

}  // namespace
}  // namespace imx
