// An MPR plane's thick slab (a plane object's "slab") projects its volume along the plane's
// normal as the reading views do: a plane with a MIP or mean slab, rendered square on from the
// feet, is the axial reading view with the same slab, within 1/255 of each PNG's bytes, and not
// the thin plane.
#include <cmath>
#include <filesystem>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <glm/gtc/matrix_transform.hpp>
#include <nlohmann/json.hpp>

#include "intermix/error.hpp"
#include "intermix/io.hpp"
#include "intermix/render.hpp"
#include "intermix/scene.hpp"
#include "intermix/volume.hpp"
#include "server/reading_views.hpp"
#include "server/viewer_state.hpp"
#include "temp_dir.hpp"

namespace imx::server {
namespace {

constexpr int kPixels = 48;

// 16^3 voxels of 1 mm about the origin whose values change along z as well as x.
void write_layers(const test::TempDir& dir) {
  VolumeData v;
  v.dims = glm::ivec3(16);
  std::vector<float> voxels(16 * 16 * 16);
  for (size_t n = 0; n < voxels.size(); ++n)
    voxels[n] = 100.0f * static_cast<float>((n % 16 / 4 + n / 256 / 3) % 4);
  v.voxels = std::move(voxels);
  v.index_to_world = glm::translate(glm::dmat4(1.0), glm::dvec3(-7.5));
  write_nrrd(v, dir / "layers.nrrd");
}

Image png_bytes(const test::TempDir& dir, const std::string& png) {
  test::write_bytes(dir / "view.png", png);
  return read_png(dir / "view.png", true);
}

// The largest difference of two images' bytes, in 1/255 steps.
float largest_gap(const Image& a, const Image& b) {
  float most = 0.0f;
  for (int y = 0; y < a.height(); ++y)
    for (int x = 0; x < a.width(); ++x)
      for (int c = 0; c < 3; ++c) most = std::max(most, std::abs(a.at(x, y)[c] - b.at(x, y)[c]));
  return most * 255.0f;
}

TEST(PlaneSlab, APlanesSlabIsTheReadingViewsSlab) {
  test::TempDir dir;
  write_layers(dir);
  for (const char* mode : {"mip", "mean"}) {
    const auto scene_with = [&](const std::string& slab) {
      return R"({
        "camera": {"eye": [0, 0, -200], "target": [0, 0, 0], "up": [0, -1, 0],
                   "projection": "orthographic", "ortho_height": 12},
        "image": {"width": 48, "height": 48},
        "objects": [
          {"name": "layers", "type": "volume", "source": {"file": "layers.nrrd"},
           "transfer_function": {"points": [[0, 1, 1, 1, 0]]}},
          {"name": "axial", "type": "plane", "volume": "layers", "center": [0, 0, 0.25],
           "normal": [0, 0, 1], "size": [40, 40], "window": [150, 400], "colormap": "grey")" +
             slab + "}]}";
    };
    const std::string slab = std::string(R"(, "slab": {"thickness": 4, "mode": ")") + mode + "\"}";
    test::write_bytes(dir / "scene.json", scene_with(slab));
    test::write_bytes(dir / "thin.json", scene_with(""));
    ViewerState state = load_viewer_state(dir / "scene.json");
    RenderOptions options;
    options.threads = 1;
    write_png(render(state.scene(), options), dir / (std::string("render-") + mode + ".png"));
    const Image rendered = read_png(dir / (std::string("render-") + mode + ".png"), true);
    write_png(render(load_scene(dir / "thin.json"), options),
              dir / (std::string("thin-") + mode + ".png"));
    const Image thin = read_png(dir / (std::string("thin-") + mode + ".png"), true);

    const nlohmann::json message = {
        {"type", "slice"},       {"view", "axial"},
        {"point", {0, 0, 0.25}}, {"width", kPixels},
        {"height", kPixels},     {"mm_per_pixel", 12.0 / kPixels},
        {"window", {150, 400}},  {"thick_slab", {{"thickness", 4}, {"mode", mode}}}};
    const Image view = png_bytes(dir, answer_slice(state, message).png);
    ASSERT_EQ(view.width(), rendered.width());
    EXPECT_LE(largest_gap(view, rendered), 1.0f + 1e-3f) << mode;
    EXPECT_GT(largest_gap(thin, rendered), 20.0f) << mode << ": the slab changed nothing";
  }
}

// The viewer's panel edits a plane's slab: the edit is written to the document (thickness 0
// takes it out), and a slab on a volume, or one of 10^6 mm, is refused and changes nothing.
TEST(PlaneSlab, AnEditSetsAndClearsThePlanesSlab) {
  test::TempDir dir;
  write_layers(dir);
  test::write_bytes(dir / "scene.json", R"({
    "objects": [
      {"name": "layers", "type": "volume", "source": {"file": "layers.nrrd"}},
      {"name": "axial", "type": "plane", "volume": "layers", "center": [0, 0, 0],
       "normal": [0, 0, 1], "size": [40, 40]}]})");
  ViewerState state = load_viewer_state(dir / "scene.json");
  const auto edit = [](const char* object, const nlohmann::json& slab) {
    return nlohmann::json{{"type", "edit"}, {"object", object}, {"slab", slab}};
  };
  ASSERT_TRUE(apply_edit(state, edit("axial", {{"thickness", 6}, {"mode", "minip"}})));
  EXPECT_EQ(state.scene().planes[0].slab, (SlabProjection{6.0, SlabMode::minip}));
  EXPECT_EQ(state.document.json()["objects"][1]["slab"]["mode"], "minip");
  EXPECT_THROW(apply_edit(state, edit("layers", {{"thickness", 6}})), Error);
  EXPECT_THROW(apply_edit(state, edit("axial", {{"thickness", 1e6}})), Error);
  EXPECT_EQ(state.scene().planes[0].slab.thickness, 6.0);
  ASSERT_TRUE(apply_edit(state, edit("axial", {{"thickness", 0}})));
  EXPECT_EQ(state.scene().planes[0].slab.thickness, 0.0);
  EXPECT_FALSE(state.document.json()["objects"][1].contains("slab"));
}

}  // namespace
}  // namespace imx::server
