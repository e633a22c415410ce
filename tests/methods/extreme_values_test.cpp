// Volumes whose finite voxel values reach the float limits render with every method and style.
#include <cfloat>
#include <cmath>
#include <memory>

#include <gtest/gtest.h>
#include <glm/gtc/matrix_transform.hpp>

#include "intermix/error.hpp"
#include "intermix/render.hpp"
#include "intermix/scene.hpp"

namespace imx {
namespace {

// 8^3 voxels alternating between -FLT_MAX, FLT_MAX, 0 and 1, with the TF on [0, 1].
Scene extreme_scene(VolumeStyle style) {
  auto data = std::make_shared<VolumeData>();
  data->dims = {8, 8, 8};
  std::vector<float> voxels(512);
  const float pattern[4] = {-FLT_MAX, FLT_MAX, 0.0f, 1.0f};
  for (size_t i = 0; i < voxels.size(); ++i) voxels[i] = pattern[(i * 7 + i / 8) % 4];
  data->voxels = std::move(voxels);
  VolumeObject v;
  v.name = "extreme";
  v.data = data;
  v.index_to_world = glm::translate(glm::dmat4(1.0), glm::dvec3(-3.5));
  v.transfer_function.points = {{0.0, glm::vec4(0.2f, 0.4f, 0.8f, 0.0f)},
                                {1.0, glm::vec4(1.0f, 0.9f, 0.7f, 0.6f)}};
  v.style = style;
  v.iso_value = 0.5;
  Scene scene;
  scene.camera.eye = {5.0, -30.0, 8.0};
  scene.camera.target = {0.0, 0.0, 0.0};
  scene.image.width = scene.image.height = 8;
  scene.volumes.push_back(v);
  scene.order.push_back({ObjectKind::volume, 0});
  return scene;
}

TEST(ExtremeVoxels, EveryMethodAndStyleGivesFinitePixels) {
  for (VolumeStyle style :
       {VolumeStyle::dvr, VolumeStyle::iso, VolumeStyle::mip, VolumeStyle::xray}) {
    Scene scene = extreme_scene(style);
    for (const std::string& method : available_methods()) {
      SCOPED_TRACE(method + " style " + std::to_string(static_cast<int>(style)));
      RenderOptions options;
      options.method = method;
      options.threads = 1;
      Image image;
      try {
        image = render(scene, options);
      } catch (const Error& e) {
        // A method may refuse a style, but never the values: DVR renders everywhere.
        EXPECT_NE(style, VolumeStyle::dvr) << e.what();
        continue;
      }
      ASSERT_EQ(image.size(), 64u);
      int lit = 0;
      for (size_t i = 0; i < image.size(); ++i) {
        const glm::vec4& p = image.data()[i];
        ASSERT_TRUE(std::isfinite(p.r) && std::isfinite(p.g) && std::isfinite(p.b) &&
                    std::isfinite(p.a));
        lit += p.a > 0.01f;
      }
      EXPECT_GT(lit, 0) << "the volume's voxels of value 1 should show";
    }
  }
}

}  // namespace
}  // namespace imx
