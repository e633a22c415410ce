// Legends read back: the labels a label map holds and shows, by name and colour, in value order;
// tractogram groups; swatches drawn in the entries' colours beside the colour bars.
#include "annotate/legend.hpp"

#include <gtest/gtest.h>

#include "annotate/keys.hpp"
#include "core/colour.hpp"
#include "have_font.hpp"
#include "intermix/error.hpp"

namespace imx {
namespace {

// Labels 0 (background), 2, 5, 7 and 3 in a 4x4x4 volume.
VolumeObject label_volume(std::vector<LabelEntry> table, bool palette_unlisted = false) {
  VolumeData d;
  d.dims = {4, 4, 4};
  std::vector<uint8_t> v(64, 0);
  v[1] = 2;
  v[2] = 5;
  v[3] = 7;
  v[4] = 3;
  d.voxels = std::move(v);
  VolumeObject o;
  o.name = "aseg";
  o.data = std::make_shared<const VolumeData>(std::move(d));
  auto map = std::make_shared<LabelMap>();
  map->entries = std::move(table);
  map->palette_unlisted = palette_unlisted;
  o.labels = map;
  return o;
}

const glm::vec3 kCaudate{0.1f, 0.6f, 0.2f}, kPutamen{0.8f, 0.3f, 0.1f};

std::vector<LabelEntry> table() {
  return {{2, "caudate", kCaudate, 1.0f, true},
          {5, "putamen", kPutamen, 1.0f, true},
          {7, "hidden", glm::vec3(1.0f), 1.0f, false},
          {9, "absent", glm::vec3(1.0f), 1.0f, true}};
}

using test::have_font;

TEST(Legend, NamesTheLabelsTheVolumeHoldsAndShows) {
  const std::optional<Legend> legend = label_legend(label_volume(table()));
  ASSERT_TRUE(legend);
  EXPECT_EQ(legend->title, "aseg");
  ASSERT_EQ(legend->entries.size(), 2u);  // 3 is not in the table, 7 hidden, 9 absent
  EXPECT_EQ(legend->entries[0].name, "caudate");
  EXPECT_EQ(legend->entries[0].colour, kCaudate);
  EXPECT_EQ(legend->entries[1].name, "putamen");
  // Without a table the palette shows every label the voxels hold but 0.
  const std::optional<Legend> palette = label_legend(label_volume({}, true));
  ASSERT_TRUE(palette);
  ASSERT_EQ(palette->entries.size(), 4u);
  EXPECT_EQ(palette->entries[1].name, "label 3");
  EXPECT_EQ(palette->entries[1].colour, default_label_color(3));
  // Not a label volume: no legend.
  VolumeObject plain = label_volume({});
  plain.labels.reset();
  EXPECT_FALSE(label_legend(plain));
}

TEST(Legend, TheSceneAsksForShownLabelMapsAndGroupedTracts) {
  Scene scene;
  scene.volumes.push_back(label_volume(table()));
  scene.order.push_back({ObjectKind::volume, 0});
  EXPECT_EQ(scene_legends(scene).size(), 1u);
  auto hidden = std::make_shared<LabelMap>(*scene.volumes[0].labels);
  hidden->shown = false;
  scene.volumes[0].labels = hidden;
  EXPECT_TRUE(scene_legends(scene).empty());
  PlaneObject plane;  // a shown plane through the hidden volume shows its labels
  plane.volume = 0;
  scene.planes.push_back(plane);
  scene.order.push_back({ObjectKind::plane, 0});
  EXPECT_EQ(scene_legends(scene).size(), 1u);

  StreamlineObject tracts;
  tracts.name = "bundles";
  auto s = std::make_shared<Streamlines>();
  s->groups = {{"AF_L", {}, glm::vec3(0.0f, 0.0f, 1.0f)}, {"CST_R", {}, std::nullopt}};
  tracts.streamlines = s;
  tracts.color = glm::vec3(0.5f);
  scene.streamlines.push_back(tracts);
  scene.order.push_back({ObjectKind::streamlines, 0});
  EXPECT_EQ(scene_legends(scene).size(), 1u);  // coloured by direction: no legend
  scene.streamlines[0].colouring = StreamlineColouring::group;
  const std::vector<Legend> legends = scene_legends(scene);
  ASSERT_EQ(legends.size(), 2u);
  EXPECT_EQ(legends[1].entries[1].name, "CST_R");
  EXPECT_EQ(legends[1].entries[1].colour, glm::vec3(0.5f));  // the object's colour
}

TEST(Legend, SwatchesAreTheEntriesColoursAndTooManyAreCounted) {
  ASSERT_TRUE(have_font())
      << "no font for legends: scripts/install-deps installs fonts-dejavu-core";
  const std::vector<Legend> legends = {*label_legend(label_volume(table()))};
  Image image(400, 300, glm::vec4(0.2f, 0.3f, 0.4f, 1.0f));
  const KeyPlacements placed = draw_keys(
      image, {}, legends, ColourBarStyle{ColourBarPosition::outside, 1.0, glm::vec3(1.0f)});
  ASSERT_EQ(placed.legends.size(), 1u);
  ASSERT_EQ(placed.legends[0].rows.size(), 2u);
  EXPECT_GT(image.width(), 400);
  const glm::vec3 colours[] = {kCaudate, kPutamen};
  for (size_t i = 0; i < 2; ++i) {
    const LegendPlacement::Row& r = placed.legends[0].rows[i];
    EXPECT_EQ(r.name, legends[0].entries[i].name);
    EXPECT_GE(r.swatch_x0, 400);
    for (int y = r.swatch_y0; y < r.swatch_y1; ++y)
      for (int x = r.swatch_x0; x < r.swatch_x1; ++x)
        ASSERT_EQ(glm::vec3(image.at(x, y)), colours[i]) << x << "," << y;
    int ink = 0;  // dark text on the white canvas
    for (int y = r.text_y0; y < r.text_y1; ++y)
      for (int x = r.text_x0; x < r.text_x1; ++x) ink += image.at(x, y).r < 0.3f;
    EXPECT_GT(ink, 5) << r.name;
  }
  // 60 labels in a short image: the rows that fit, the last "+N more" counting the rest.
  Legend many{"parcels", {}, 0};
  for (int i = 0; i < 60; ++i)
    many.entries.push_back({"parcel " + std::to_string(i), glm::vec3(1.0f)});
  Image small(200, 120);
  const KeyPlacements cut = draw_keys(small, {}, std::vector<Legend>{many}, ColourBarStyle{});
  ASSERT_EQ(cut.legends.size(), 1u);
  const auto& rows = cut.legends[0].rows;
  ASSERT_GE(rows.size(), 2u);
  EXPECT_EQ(rows.back().name, "+" + std::to_string(60 - (rows.size() - 1)) + " more");
  EXPECT_LE(rows.back().text_y1, small.height());
}

}  // namespace
}  // namespace imx
