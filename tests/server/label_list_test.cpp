// The viewer's label lists: a label volume's `state` names the labels its voxels hold, as its table
// or the palette draws them; a label edit writes labels.overrides, shows in the next state, and
// renders like a scene file with the same table; bad label edits change nothing.
#include "server/label_list.hpp"

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <vector>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "intermix/io.hpp"
#include "intermix/render.hpp"
#include "server/reading_views.hpp"
#include "server/viewer_state.hpp"
#include "temp_dir.hpp"

namespace imx::server {
namespace {

using Json = nlohmann::json;
using test::TempDir;

// 12³ voxels: background 0, then labels 2 and 7 in two halves of a centred block.
std::filesystem::path write_labels(const TempDir& dir) {
  VolumeData v;
  v.dims = {12, 12, 12};
  std::vector<uint8_t> voxels(12 * 12 * 12, 0);
  for (int z = 3; z < 9; ++z)
    for (int y = 3; y < 9; ++y)
      for (int x = 3; x < 9; ++x)
        voxels[static_cast<size_t>((z * 12 + y) * 12 + x)] = x < 6 ? 2 : 7;
  v.voxels = VoxelBuffer<uint8_t>(std::move(voxels));
  v.index_to_world = glm::dmat4(4.0);
  v.index_to_world[3] = glm::dvec4(-22.0, -22.0, -22.0, 1.0);
  const std::filesystem::path file = dir.path() / "seg.nrrd";
  write_nrrd(v, file);
  return file;
}

std::filesystem::path write_scene(const TempDir& dir, const Json& labels) {
  write_labels(dir);
  Json object = {
      {"name", "seg"}, {"type", "volume"}, {"source", {{"file", "seg.nrrd"}}}, {"style", "labels"}};
  if (!labels.is_null()) object["labels"] = labels;
  const Json scene = {{"camera", {{"eye", {0, -200, 0}}, {"target", {0, 0, 0}}, {"up", {0, 0, 1}}}},
                      {"image", {{"width", 32}, {"height", 32}}},
                      {"objects", {object}}};
  const std::filesystem::path file = dir.path() / "scene.json";
  std::ofstream(file) << scene.dump();
  return file;
}

Json state_labels(const ViewerState& state) {
  return describe_state(state)["objects"][0]["labels"];
}

// The label under the crosshair by name: the table's, else "label N"; nothing outside the grid.
TEST(LabelList, TheProbeNamesTheLabelUnderTheCrosshair) {
  TempDir dir;
  const Json table = {{"table", {{{"value", 2}, {"name", "liver"}}}}};
  const ViewerState state = load_viewer_state(write_scene(dir, table));
  // Voxel (4, 5, 5) holds 2, (7, 5, 5) holds 7 (in no table row), (0, 0, 0) holds 0.
  const auto probe = [&](const glm::dvec3& index) {
    const glm::dvec3 p = -22.0 + 4.0 * index;
    return answer_probe(state, {{"type", "probe"}, {"point", {p.x, p.y, p.z}}})["values"][0];
  };
  EXPECT_EQ(probe({4, 5, 5})["label"], "liver");
  EXPECT_EQ(probe({7, 5, 5})["label"], "label 7");
  EXPECT_EQ(probe({7, 5, 5})["value"], 7.0);
  EXPECT_FALSE(probe({-3, 0, 0}).contains("label"));  // outside the grid
}

TEST(LabelList, ListsTheLabelsTheVoxelsHold) {
  TempDir dir;
  const Json table = {{"table",
                       {{{"value", 2}, {"name", "liver"}, {"color", {1, 0, 0}}},
                        {{"value", 5}, {"name", "spleen"}}}}};
  const ViewerState state = load_viewer_state(write_scene(dir, table));
  const Json labels = state_labels(state);
  ASSERT_EQ(labels.size(), 3u);  // 0, 2, 7 occur; 5 is in the table only
  EXPECT_EQ(labels[0]["value"], 0);
  EXPECT_FALSE(labels[0]["visible"]);  // background
  EXPECT_EQ(labels[1]["name"], "liver");
  EXPECT_EQ(labels[1]["color"], Json({1.0, 0.0, 0.0}));
  EXPECT_TRUE(labels[1]["visible"]);
  EXPECT_EQ(labels[2]["value"], 7);
  EXPECT_FALSE(labels[2]["visible"]);  // a table names what shows
}

TEST(LabelList, AnEditWritesOverridesAndRendersAsTheSameTableInAFile) {
  TempDir dir;
  ViewerState state = load_viewer_state(write_scene(dir, nullptr));  // the default palette
  EXPECT_TRUE(state_labels(state)[2]["visible"]);
  const Json edit = {{"type", "edit"},
                     {"object", "seg"},
                     {"labels",
                      {{{"value", 7}, {"visible", false}},
                       {{"value", 2}, {"color", {0, 1, 0}}, {"opacity", 0.5}}}}};
  EXPECT_TRUE(apply_edit(state, edit));
  const Json labels = state_labels(state);
  EXPECT_FALSE(labels[2]["visible"]);
  EXPECT_EQ(labels[1]["color"], Json({0.0, 1.0, 0.0}));
  EXPECT_DOUBLE_EQ(labels[1]["opacity"].get<double>(), 0.5);
  // A second edit of one field keeps the other fields of that label.
  apply_edit(
      state,
      Json{{"type", "edit"}, {"object", "seg"}, {"labels", {{{"value", 2}, {"visible", true}}}}});
  EXPECT_EQ(state_labels(state)[1]["color"], Json({0.0, 1.0, 0.0}));
  // The same looks written as an inline table render the same image.
  TempDir other;
  const Json table = {
      {"table", {{{"value", 2}, {"name", "label 2"}, {"color", {0, 1, 0}}, {"opacity", 0.5}}}}};
  const Scene want = load_scene(write_scene(other, table));
  const Image a = render(state.scene()), b = render(want);
  ASSERT_EQ(a.size(), b.size());
  EXPECT_TRUE(std::equal(a.data(), a.data() + a.size(), b.data()));
  double lit = 0.0;
  for (size_t i = 0; i < a.size(); ++i) lit += a.data()[i].g;
  EXPECT_GT(lit, 0.0);  // label 2 shows, green
}

TEST(LabelList, BadLabelEditsChangeNothing) {
  TempDir dir;
  ViewerState state = load_viewer_state(write_scene(dir, nullptr));
  const Json before = state.document.json();
  for (const Json& labels : {Json{{{"value", 2.5}}}, Json{{{"value", 2}, {"opacity", 2}}},
                             Json{{{"value", 2}, {"shape", "round"}}}, Json("all")}) {
    const Json edit = {{"type", "edit"}, {"object", "seg"}, {"labels", labels}};
    EXPECT_THROW(apply_edit(state, edit), Error) << labels.dump();
    EXPECT_EQ(state.document.json(), before);
  }
}

}  // namespace
}  // namespace imx::server
