#include "volume/ray_shading.hpp"

#include <gtest/gtest.h>

#include <random>
#include <vector>

namespace imx {
namespace {

// RayShading must light a premultiplied sample exactly as blinn_phong lights its straight colour,
// for headlights and directional lights, any normal length (zero included) and either side; its
// tabulated specular power stays within the table's 1e-4.
TEST(RayShading, MatchesBlinnPhong) {
  std::mt19937 rng(4);
  std::uniform_real_distribution<float> u(0.0f, 1.0f), s(-1.0f, 1.0f);
  auto unit = [&] { return glm::normalize(glm::vec3(s(rng), s(rng), s(rng)) + 1e-3f); };
  for (int trial = 0; trial < 200; ++trial) {
    Shading sh{true, u(rng), u(rng), u(rng), trial % 2 ? 32.0f : 1.0f + 60.0f * u(rng)};
    std::vector<ShadingLight> lights(1 + trial % 6);  // up to 6: beyond kMaxLights too
    for (size_t i = 0; i < lights.size(); ++i)
      lights[i] = {i == 0, unit(), glm::vec3(u(rng), u(rng), u(rng)) * 2.0f};
    glm::vec3 to_eye = unit();
    SpecularTable specular(sh.shininess);
    RayShading shading(sh, specular, lights, to_eye);
    for (int k = 0; k < 20; ++k) {
      glm::vec4 c(u(rng), u(rng), u(rng), 0.0f);
      c.a = std::max({c.r, c.g, c.b}) + 0.1f * u(rng);
      glm::vec3 n = k == 0 ? glm::vec3(0.0f) : unit() * (0.01f + 100.0f * u(rng));
      glm::vec3 expected = blinn_phong(sh, glm::vec3(c) / c.a, n, to_eye, lights) * c.a;
      glm::vec4 got = shading.apply(c, n);
      EXPECT_EQ(got.a, c.a);
      for (int i = 0; i < 3; ++i) EXPECT_NEAR(got[i], expected[i], 3e-4f * (1.0f + expected[i]));
    }
  }
}

}  // namespace
}  // namespace imx
