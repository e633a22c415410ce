// Work that scales with a user number has a cap: steps per ray are checked before any march.
#include <string>

#include <gtest/gtest.h>
#include <glm/gtc/matrix_transform.hpp>

#include "homogeneous_volume.hpp"
#include "intermix/error.hpp"
#include "intermix/render.hpp"

namespace imx {
namespace {

Scene fog_scene() {
  Scene scene;
  scene.camera.eye = {0.0, -60.0, 0.0};
  scene.image.width = scene.image.height = 4;
  scene.volumes.push_back(test::homogeneous_volume(0.05f, glm::vec3(1.0f)));
  scene.order.push_back({ObjectKind::volume, 0});
  return scene;
}

std::string render_error(const Scene& scene, const std::string& method) {
  RenderOptions options;
  options.method = method;
  options.threads = 1;
  try {
    render(scene, options);
  } catch (const Error& e) {
    return e.what();
  }
  return {};
}

TEST(StepLimits, ATinyStepIsRefusedByEveryMethod) {
  Scene scene = fog_scene();
  scene.render.step_mm = 1e-5;  // 20 mm across: 2 million steps
  for (const std::string& method : available_methods()) {
    std::string message = render_error(scene, method);
    EXPECT_NE(message.find("render.step_mm gives a ray step of 1e-05 mm"), std::string::npos)
        << method << ": " << message;
    EXPECT_NE(message.find("volume 'fog'"), std::string::npos) << method << ": " << message;
  }
  scene.render.step_mm = 1e-320;  // a denormal, 0 as a float
  EXPECT_NE(render_error(scene, "mdvr").find("render.step_mm"), std::string::npos);
  scene.render.step_mm = 0.5;
  EXPECT_EQ(render_error(scene, "mdvr"), "");
}

TEST(StepLimits, ATinyReferenceFractionIsRefused) {
  Scene scene = fog_scene();
  scene.render.reference_step_fraction = 1e-9;
  std::string message = render_error(scene, "reference");
  EXPECT_NE(message.find("render.reference_step_fraction (1e-09)"), std::string::npos) << message;
}

TEST(StepLimits, NeedleVoxelsAreRefusedWithTheirPitch) {
  Scene scene = fog_scene();
  // 0.001 x 0.001 x 1000 mm voxels: the pitch sets a 0.001 mm step along a 20 km column.
  scene.volumes[0].index_to_world = glm::scale(glm::dmat4(1.0), glm::dvec3(1e-3, 1e-3, 1000.0));
  for (const char* method : {"mdvr", "zslab", "dfb", "reference"}) {
    std::string message = render_error(scene, method);
    EXPECT_NE(message.find("the smallest voxel pitch (0.001 mm)"), std::string::npos)
        << method << ": " << message;
  }
}

}  // namespace
}  // namespace imx
