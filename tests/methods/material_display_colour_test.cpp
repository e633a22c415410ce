// What you give is what you see (docs/colour.md): a mesh's material colour, as the scene file
// gives it, is the colour of its pixels in the PNG (within 1/255) where it is opaque and unlit,
// and where it is lit head-on at full diffuse with no ambient or specular part.
#include <filesystem>
#include <string>

#include <fmt/format.h>
#include <gtest/gtest.h>

#include "intermix/io.hpp"
#include "intermix/render.hpp"
#include "intermix/scene.hpp"
#include "png_centre.hpp"
#include "temp_dir.hpp"

namespace imx {
namespace {

// A box facing the camera square on, in a material of `given` (bytes) and `shading`.
Scene box_scene(const glm::ivec3& given, const std::string& shading) {
  const glm::vec3 c = glm::vec3(given) / 255.0f;
  const std::string text = fmt::format(
      R"({{"camera": {{"eye": [0, -200, 0], "target": [0, 0, 0], "up": [0, 0, 1],
                      "projection": "orthographic", "ortho_height": 40}},
          "image": {{"width": 16, "height": 16}},
          "objects": [{{"name": "box", "type": "mesh",
                        "source": {{"primitive": "box", "size": [20, 20, 20]}},
                        "material": {{"color": [{}, {}, {}], "shading": {}}}}}]}})",
      c.r, c.g, c.b, shading);
  return parse_scene(text, {}, "scene.json");
}

TEST(MaterialDisplayColour, AnUnlitMeshShowsItsMaterialColour) {
  test::TempDir dir;
  const glm::ivec3 given(204, 153, 51);
  const Scene scene = box_scene(given, R"({"enabled": false})");
  for (const char* method : {"reference", "peel", "zslab"}) {
    const glm::ivec3 got = test::centre_png_bytes(dir, scene, method);
    for (int ch = 0; ch < 3; ++ch)
      EXPECT_NEAR(got[ch], given[ch], 1) << method << " channel " << ch;
  }
}

TEST(MaterialDisplayColour, AMeshLitHeadOnAtFullDiffuseShowsItsMaterialColour) {
  test::TempDir dir;
  const glm::ivec3 given(40, 220, 60);
  const Scene scene =
      box_scene(given, R"({"ambient": 0, "diffuse": 1, "specular": 0, "shininess": 1})");
  const glm::ivec3 got = test::centre_png_bytes(dir, scene, "reference");
  for (int ch = 0; ch < 3; ++ch) EXPECT_NEAR(got[ch], given[ch], 1) << "channel " << ch;
}

}  // namespace
}  // namespace imx
