#include <gtest/gtest.h>

#include "raster/shade_fragment.hpp"

namespace imx {
namespace {

TEST(ShadeFragment, WindowLevelMapsTheWindowLinearlyOntoZeroToOne) {
  EXPECT_FLOAT_EQ(window_level(40.0f, 40.0f, 400.0f), 0.5f);
  EXPECT_FLOAT_EQ(window_level(-160.0f, 40.0f, 400.0f), 0.0f);
  EXPECT_FLOAT_EQ(window_level(240.0f, 40.0f, 400.0f), 1.0f);
  EXPECT_FLOAT_EQ(window_level(-1000.0f, 40.0f, 400.0f), 0.0f);
  EXPECT_FLOAT_EQ(window_level(1000.0f, 40.0f, 400.0f), 1.0f);
  EXPECT_FLOAT_EQ(window_level(140.0f, 40.0f, 400.0f), 0.75f);
}

TEST(ShadeFragment, PlaneIsUnlitAndPremultiplied) {
  glm::vec4 c = shade_plane_fragment({1.0f, 0.5f, 0.25f}, 0.5f, 0.8f);
  EXPECT_FLOAT_EQ(c.r, 0.4f);
  EXPECT_FLOAT_EQ(c.g, 0.2f);
  EXPECT_FLOAT_EQ(c.b, 0.1f);
  EXPECT_FLOAT_EQ(c.a, 0.5f);
}

TEST(ShadeFragment, MeshIsLitByBlinnPhongAndPremultiplied) {
  Material m;
  m.color = {0.2f, 0.4f, 0.8f};
  m.opacity = 0.5f;
  m.shading = {true, 0.1f, 0.6f, 0.3f, 16.0f};
  ShadingLight head;  // headlight, white
  const glm::vec3 to_eye{0.0f, 0.0f, 1.0f};
  // Head-on: ambient + diffuse + full specular.
  glm::vec4 c = shade_mesh_fragment(m, {0.0f, 0.0f, 2.0f}, to_eye, std::span(&head, 1));
  for (int i = 0; i < 3; ++i) EXPECT_NEAR(c[i], ((0.1f + 0.6f) * m.color[i] + 0.3f) * 0.5f, 1e-6f);
  EXPECT_FLOAT_EQ(c.a, 0.5f);
  // Shading disabled: the flat colour, premultiplied.
  m.shading.enabled = false;
  c = shade_mesh_fragment(m, {1.0f, 0.0f, 0.0f}, to_eye, std::span(&head, 1));
  for (int i = 0; i < 3; ++i) EXPECT_FLOAT_EQ(c[i], m.color[i] * 0.5f);
}

}  // namespace
}  // namespace imx
