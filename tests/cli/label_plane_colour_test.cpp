// What you give is what you see (docs/colour.md): an MPR plane through a label volume, rendered
// by `intermix render` to a PNG, shows each label in its colour table's colour, byte for byte as
// FreeSurfer's LUT gives it (within 1/255), as the viewer's reading views and 3D Slicer do.
#include <algorithm>
#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include <fmt/format.h>
#include <gtest/gtest.h>
#include <glm/gtc/matrix_transform.hpp>

#include "cli_runner.hpp"
#include "intermix/io.hpp"
#include "intermix/volume.hpp"
#include "temp_dir.hpp"

namespace imx {
namespace {

struct LutRow {
  int value;
  const char* name;
  glm::ivec3 rgb;  // 0-255, as the LUT file writes it
};

// Colours far from the sRGB curve's fixed points 0 and 255, so that a colour taken as linear and
// encoded (the old bug: (40, 220, 60) drawn as (110, 239, 133)) cannot pass.
const std::vector<LutRow> kTable = {{1, "Left-Cerebral-White-Matter", {40, 220, 60}},
                                    {2, "Left-Cerebral-Cortex", {205, 62, 78}},
                                    {3, "Left-Lateral-Ventricle", {120, 18, 134}},
                                    {4, "Left-Thalamus", {0, 118, 14}}};
constexpr int kSide = 16;  // voxels of 1 mm; four 8 x 8 quadrants in x and y, one label each

int label_at(int i, int j) {
  return 1 + (i >= kSide / 2 ? 1 : 0) + (j >= kSide / 2 ? 2 : 0);
}

TEST(LabelPlaneColour, APngShowsTheTablesColoursOnAnMprPlane) {
  test::TempDir dir;
  VolumeData v;
  v.dims = glm::ivec3(kSide, kSide, 4);
  std::vector<uint8_t> voxels(static_cast<size_t>(kSide * kSide * 4));
  for (int k = 0; k < 4; ++k)
    for (int j = 0; j < kSide; ++j)
      for (int i = 0; i < kSide; ++i)
        voxels[static_cast<size_t>((k * kSide + j) * kSide + i)] =
            static_cast<uint8_t>(label_at(i, j));
  v.voxels = std::move(voxels);
  const double c = 0.5 * (kSide - 1);
  v.index_to_world = glm::translate(glm::dmat4(1.0), glm::dvec3(-c, -c, -1.5));
  write_nrrd(v, dir / "seg.nrrd");
  std::string lut = "#No. Label Name R G B A\n0 Unknown 0 0 0 0\n";
  for (const LutRow& row : kTable)
    lut += fmt::format("{} {} {} {} {} 0\n", row.value, row.name, row.rgb.r, row.rgb.g, row.rgb.b);
  test::write_bytes(dir / "lut.txt", lut);
  // An axial plane seen from below, square on: each quadrant of the image is one label's.
  const std::string scene = R"({
    "camera": {"eye": [0, 0, -100], "target": [0, 0, 0], "up": [0, -1, 0],
               "projection": "orthographic", "ortho_height": 16},
    "image": {"width": 64, "height": 64},
    "objects": [
      {"name": "seg", "type": "volume", "source": {"file": "seg.nrrd"}, "style": "labels",
       "labels": {"file": "lut.txt"}, "visible": false},
      {"name": "axial", "type": "plane", "volume": "seg", "center": [0, 0, 0],
       "normal": [0, 0, 1], "size": [40, 40]}]})";
  test::write_bytes(dir / "scene.json", scene);
  const test::CliResult r = test::run_cli("render " + (dir / "scene.json").string() + " -o " +
                                          (dir / "out.png").string());
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const Image png = read_png(dir / "out.png", true);  // the stored bytes, not decoded
  ASSERT_EQ(png.width(), 64);
  // Each quadrant of the image is one label's (which one depends on the view, not checked
  // here): a block about its middle, away from the boundaries' blends, is that label's colour.
  std::vector<int> seen;
  for (const glm::ivec2 centre :
       {glm::ivec2(16, 16), glm::ivec2(48, 16), glm::ivec2(16, 48), glm::ivec2(48, 48)}) {
    const glm::vec4 mid = png.at(centre.x, centre.y);
    const glm::ivec3 got(glm::round(glm::vec3(mid) * 255.0f));
    int match = -1;
    for (size_t k = 0; k < kTable.size(); ++k)
      if (glm::all(glm::lessThanEqual(glm::abs(got - kTable[k].rgb), glm::ivec3(1))))
        match = static_cast<int>(k);
    ASSERT_GE(match, 0) << "pixel (" << centre.x << ", " << centre.y << ") is (" << got.r << ", "
                        << got.g << ", " << got.b << "), no colour of the table";
    seen.push_back(match);
    for (int dy = -4; dy <= 4; ++dy)
      for (int dx = -4; dx <= 4; ++dx) {
        const glm::vec4 p = png.at(centre.x + dx, centre.y + dy);
        for (int ch = 0; ch < 3; ++ch)
          ASSERT_NEAR(p[ch] * 255.0f,
                      static_cast<float>(kTable[static_cast<size_t>(match)].rgb[ch]), 1.0f + 1e-3f)
              << kTable[static_cast<size_t>(match)].name << " at (" << centre.x + dx << ", "
              << centre.y + dy << ") channel " << ch;
      }
  }
  std::sort(seen.begin(), seen.end());
  EXPECT_EQ(seen, (std::vector<int>{0, 1, 2, 3}));  // every label shows, each in its own colour
}

}  // namespace
}  // namespace imx
