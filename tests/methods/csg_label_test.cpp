// A label as a CSG primitive ("seg:liver"): the label volume stands for that label alone, so the
// expression renders what the same scene renders with a table showing only that label; names
// that are no label, a plain volume with a colon and two labels of one object are refused.
#include <filesystem>
#include <fstream>
#include <vector>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "expect_error.hpp"
#include "intermix/io.hpp"
#include "intermix/render.hpp"
#include "intermix/scene.hpp"
#include "temp_dir.hpp"

namespace imx {
namespace {

using Json = nlohmann::json;

// 16³ voxels of 3 mm: label 2 (liver) on one side of a block, 7 (spleen) on the other.
void write_labels(const std::filesystem::path& file) {
  VolumeData v;
  v.dims = {16, 16, 16};
  std::vector<uint8_t> voxels(16 * 16 * 16, 0);
  for (int z = 3; z < 13; ++z)
    for (int y = 3; y < 13; ++y)
      for (int x = 2; x < 14; ++x)
        voxels[static_cast<size_t>((z * 16 + y) * 16 + x)] = x < 8 ? 2 : 7;
  v.voxels = VoxelBuffer<uint8_t>(std::move(voxels));
  v.index_to_world = glm::dmat4(3.0);
  v.index_to_world[3] = glm::dvec4(-22.5, -22.5, -22.5, 1.0);
  write_nrrd(v, file);
}

Scene load(const test::TempDir& dir, const Json& table, const Json& csg) {
  // Written once per folder: a file this process has read is never written over (issue 48).
  if (!std::filesystem::exists(dir.path() / "seg.nrrd")) write_labels(dir.path() / "seg.nrrd");
  Json scene = {{"camera", {{"eye", {0, -200, 0}}, {"target", {0, 0, 0}}, {"up", {0, 0, 1}}}},
                {"image", {{"width", 40}, {"height", 40}}},
                {"render", {{"method", "csg"}}},
                {"objects",
                 {{{"name", "seg"},
                   {"type", "volume"},
                   {"source", {{"file", "seg.nrrd"}}},
                   {"style", "labels"},
                   {"labels", {{"table", table}}}},
                  {{"name", "ball"},
                   {"type", "mesh"},
                   {"source", {{"primitive", "sphere"}, {"radius", 9}, {"segments", 24}}},
                   {"transform", {{"translate", {-10, -20, 0}}}},
                   {"material", {{"color", {0.2, 0.8, 0.3}}, {"opacity", 1}}}}}},
                {"csg", csg}};
  const std::filesystem::path file = dir.path() / "scene.json";
  std::ofstream(file) << scene.dump();
  return load_scene(file);
}

const Json kTable = {{{"value", 2}, {"name", "liver"}, {"color", {0.9, 0.4, 0.3}}},
                     {{"value", 7}, {"name", "spleen"}, {"color", {0.3, 0.4, 0.9}}}};

bool same(const Image& a, const Image& b) {
  return a.size() == b.size() && std::equal(a.data(), a.data() + a.size(), b.data());
}

TEST(CsgLabel, ALabelPrimitiveIsTheVolumeShowingThatLabelAlone) {
  test::TempDir a, b, c;
  const Json liver_only = {
      {{"value", 2}, {"name", "liver"}, {"color", {0.9, 0.4, 0.3}}},
      {{"value", 7}, {"name", "spleen"}, {"color", {0.3, 0.4, 0.9}}, {"visible", false}}};
  const Json expression = {{"op", "difference"}, {"a", "seg:liver"}, {"b", "ball"}};
  const Image by_label = render(load(a, kTable, expression));
  const Image by_table =
      render(load(b, liver_only, {{"op", "difference"}, {"a", "seg"}, {"b", "ball"}}));
  EXPECT_TRUE(same(by_label, by_table));
  double liver = 0.0;  // the liver half shows, in its red
  for (size_t i = 0; i < by_label.size(); ++i) liver += by_label.data()[i].r - by_label.data()[i].b;
  EXPECT_GT(liver, 1.0);
  // ... and not the whole label volume: the spleen half is gone.
  const Image whole = render(load(c, kTable, {{"op", "difference"}, {"a", "seg"}, {"b", "ball"}}));
  EXPECT_FALSE(same(by_label, whole));
  // By value too.
  test::TempDir d;
  EXPECT_TRUE(same(by_label,
                   render(load(d, kTable, {{"op", "difference"}, {"a", "seg:2"}, {"b", "ball"}}))));
}

TEST(CsgLabel, BadLabelPrimitivesAreOneClearError) {
  test::TempDir dir;
  EXPECT_NE(test::error_of([&] {
              load(dir, kTable, {{"op", "difference"}, {"a", "seg:livr"}, {"b", "ball"}});
            }).find("'seg' has no label 'livr' (did you mean 'liver'"),
            std::string::npos);
  EXPECT_NE(test::error_of([&] {
              load(dir, kTable, {{"op", "union"}, {"a", "seg:liver"}, {"b", "seg:spleen"}});
            }).find("one volume object is one primitive"),
            std::string::npos);
  EXPECT_NE(test::error_of([&] {
              load(dir, kTable, {{"op", "difference"}, {"a", "seg"}, {"b", "ball:3"}});
            }).find("'ball' is not a label volume"),
            std::string::npos);
}

}  // namespace
}  // namespace imx
