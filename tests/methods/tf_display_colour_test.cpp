// What you give is what you see (docs/colour.md): an opaque, unshaded volume of one value shows
// its transfer function's colour, as the scene file gives it, in the PNG (within 1/255), by every
// method, from explicit points and from a 3D Slicer preset's colour alike.
#include <cmath>
#include <filesystem>
#include <string>
#include <vector>

#include <fmt/format.h>
#include <gtest/gtest.h>
#include <glm/gtc/matrix_transform.hpp>

#include "intermix/io.hpp"
#include "intermix/render.hpp"
#include "intermix/scene.hpp"
#include "intermix/volume.hpp"
#include "png_centre.hpp"
#include "temp_dir.hpp"

namespace imx {
namespace {

// A 12^3 volume of one value about the origin, seen square on from the front.
std::string scene_text(const std::string& transfer_function) {
  return R"({"camera": {"eye": [0, -200, 0], "target": [0, 0, 0], "up": [0, 0, 1],
                        "projection": "orthographic", "ortho_height": 40},
             "image": {"width": 16, "height": 16},
             "objects": [{"name": "one", "type": "volume", "source": {"file": "one.nrrd"},
                          "transfer_function": )" +
         transfer_function + "}]}";
}

void write_volume(const test::TempDir& dir, float value) {
  VolumeData v;
  v.dims = glm::ivec3(12);
  v.voxels = std::vector<float>(12 * 12 * 12, value);
  v.index_to_world = glm::translate(glm::dmat4(1.0), glm::dvec3(-5.5));
  write_nrrd(v, dir / "one.nrrd");
}

TEST(TfDisplayColour, AnOpaqueUnshadedVolumeShowsItsPointsColour) {
  test::TempDir dir;
  write_volume(dir, 7.0f);
  const glm::ivec3 given(230, 128, 51);  // [0.9, 0.5, 0.2] as a colour chooser gives it
  const glm::vec3 c = glm::vec3(given) / 255.0f;
  const std::string tf = fmt::format(
      R"({{"points": [[0, {0}, {1}, {2}, 1], [10, {0}, {1}, {2}, 1]]}})", c.r, c.g, c.b);
  const Scene scene = parse_scene(scene_text(tf), dir.path(), "scene.json");
  ASSERT_FALSE(scene.volumes.at(0).shading.enabled);
  for (const char* method : {"reference", "mdvr", "zslab", "dfb"}) {
    const glm::ivec3 got = test::centre_png_bytes(dir, scene, method);
    for (int ch = 0; ch < 3; ++ch)
      EXPECT_NEAR(got[ch], given[ch], 1) << method << " channel " << ch;
  }
}

// A Slicer preset's colour is a display colour too: at one of its colour points (ct-bone's
// (0.905882, 0.815686, 0.552941) at 641.385 HU, opacity 0.72 per mm), 12 mm of it are opaque and
// show that colour. The shading the preset asks for is switched off.
TEST(TfDisplayColour, AnOpaqueUnshadedVolumeShowsASlicerPresetsColour) {
  test::TempDir dir;
  write_volume(dir, 641.385f);
  Scene scene = parse_scene(scene_text(R"({"preset": "ct-bone"})"), dir.path(), "scene.json");
  scene.volumes.at(0).shading.enabled = false;
  const glm::ivec3 given(231, 208, 141);  // Slicer's CT-Bone colour there, in bytes
  for (const char* method : {"reference", "mdvr"}) {
    const glm::ivec3 got = test::centre_png_bytes(dir, scene, method);
    for (int ch = 0; ch < 3; ++ch)
      EXPECT_NEAR(got[ch], given[ch], 1) << method << " channel " << ch;
  }
}

}  // namespace
}  // namespace imx
