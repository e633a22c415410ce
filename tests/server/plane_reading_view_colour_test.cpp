// The 2-D reading views and the MPR planes of a render agree (docs/colour.md): an axial plane
// through a volume in its grey colour map and a window, rendered square on from the feet, is the
// viewer's axial reading view of that volume through the same window, pixel for pixel within
// 1/255 of each PNG's bytes. The window's middle is mid-grey (128) in both, as in every viewer.
#include <filesystem>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <glm/gtc/matrix_transform.hpp>
#include <nlohmann/json.hpp>

#include "intermix/io.hpp"
#include "intermix/render.hpp"
#include "intermix/volume.hpp"
#include "server/reading_views.hpp"
#include "server/viewer_state.hpp"
#include "temp_dir.hpp"

namespace imx::server {
namespace {

constexpr int kPixels = 48;

// 16^3 voxels of 1 mm about the origin in four blocks along x, values 0, 100, 200 and 300, so
// that the window [150, 400] (centre, width) shows them at t = 0.125, 0.375, 0.625 and 0.875.
void write_blocks(const test::TempDir& dir) {
  VolumeData v;
  v.dims = glm::ivec3(16);
  std::vector<float> voxels(16 * 16 * 16);
  for (size_t n = 0; n < voxels.size(); ++n) voxels[n] = 100.0f * static_cast<float>(n % 16 / 4);
  v.voxels = std::move(voxels);
  v.index_to_world = glm::translate(glm::dmat4(1.0), glm::dvec3(-7.5));
  write_nrrd(v, dir / "blocks.nrrd");
}

// A PNG's stored bytes (straight, not decoded).
Image png_bytes(const test::TempDir& dir, const std::string& png) {
  test::write_bytes(dir / "view.png", png);
  return read_png(dir / "view.png", true);
}

TEST(PlaneReadingViewColour, AGreyPlaneIsTheReadingViewOfItsVolume) {
  test::TempDir dir;
  write_blocks(dir);
  // Seen from the feet with anterior up, as the axial reading view shows a slice: screen right
  // is +x (the patient's left), screen down +y (posterior); 12 mm across the 48 pixels.
  const std::string scene = R"({
    "camera": {"eye": [0, 0, -200], "target": [0, 0, 0], "up": [0, -1, 0],
               "projection": "orthographic", "ortho_height": 12},
    "image": {"width": 48, "height": 48},
    "objects": [
      {"name": "blocks", "type": "volume", "source": {"file": "blocks.nrrd"},
       "transfer_function": {"points": [[0, 1, 1, 1, 0]]}},
      {"name": "axial", "type": "plane", "volume": "blocks", "center": [0, 0, 0.25],
       "normal": [0, 0, 1], "size": [40, 40], "window": [150, 400], "colormap": "grey"}]})";
  test::write_bytes(dir / "scene.json", scene);
  ViewerState state = load_viewer_state(dir / "scene.json");
  RenderOptions options;
  options.threads = 1;
  write_png(render(state.scene(), options), dir / "render.png");
  const Image rendered = read_png(dir / "render.png", true);

  const nlohmann::json message = {{"type", "slice"},       {"view", "axial"},
                                  {"point", {0, 0, 0.25}}, {"width", kPixels},
                                  {"height", kPixels},     {"mm_per_pixel", 12.0 / kPixels},
                                  {"window", {150, 400}}};
  const Image view = png_bytes(dir, answer_slice(state, message).png);
  ASSERT_EQ(view.width(), rendered.width());
  ASSERT_EQ(view.height(), rendered.height());
  int differ = 0;
  for (int y = 0; y < kPixels; ++y)
    for (int x = 0; x < kPixels; ++x)
      for (int c = 0; c < 3; ++c)
        if (std::abs(view.at(x, y)[c] - rendered.at(x, y)[c]) * 255.0f > 1.0f + 1e-3f) {
          if (++differ <= 5)
            ADD_FAILURE() << "pixel (" << x << ", " << y << ") channel " << c << ": view "
                          << view.at(x, y)[c] * 255.0f << ", render "
                          << rendered.at(x, y)[c] * 255.0f;
        }
  EXPECT_EQ(differ, 0);
  // The window's middle is display mid-grey: value 200 (t = 0.625) at x = +2.5 mm, 130 of 255.
  EXPECT_NEAR(view.at(34, 24).r * 255.0f, 0.625f * 255.0f, 1.0f);
}

}  // namespace
}  // namespace imx::server
