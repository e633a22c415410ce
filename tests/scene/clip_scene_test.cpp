// Tests for the volumes' "clip" lists (SPEC §7 clip geometry): names resolved to closed meshes,
// inward meshes turned outward, one error line with its JSON path per fault.
#include <filesystem>
#include <string>
#include <vector>

#include <fmt/format.h>
#include <gtest/gtest.h>

#include "intermix/scene.hpp"
#include "io/mesh_topology.hpp"
#include "test_helpers.hpp"

namespace imx {
namespace {

using test::error_of;
using test::parse;
using test::parse_error;

// Volumes "ct" and "pet" (clip lists given), meshes "ball" and "brick", an open "sheet", a
// plane "axial", and `more` objects.
std::string scene(const std::string& ct_clip, const std::string& pet_clip = "",
                  const std::string& more = "") {
  auto volume = [](const char* name, const std::string& clip) {
    return fmt::format(
        R"({{"name": "{}", "type": "volume", "source": {{"phantom": "cube", "size": 8}},
            "transfer_function": {{"points": [[0, 1, 1, 1, 0], [100, 1, 1, 1, 1]]}}{}}})",
        name, clip.empty() ? "" : R"(, "clip": )" + clip);
  };
  return R"({"objects": [)" + volume("ct", ct_clip) + ", " + volume("pet", pet_clip) + R"(,
    {"name": "ball", "type": "mesh", "source": {"primitive": "sphere", "radius": 10}},
    {"name": "brick", "type": "mesh", "source": {"primitive": "box", "size": 20}},
    {"name": "sheet", "type": "mesh", "source": {"primitive": "quad", "size": 20}},
    {"name": "axial", "type": "plane", "center": [0, 0, 5], "normal": [0, 0, 1], "size": 50})" +
         more + "]}";
}

TEST(ClipScene, NamesResolveToMeshesWithTheirKeep) {
  const Scene s = parse(scene(R"([{"mesh": "ball", "keep": "outside"},
                                  {"mesh": "brick", "keep": "inside"}])",
                              R"([{"mesh": "ball", "keep": "inside"}])"));
  ASSERT_EQ(s.volumes.size(), 2u);
  ASSERT_EQ(s.volumes[0].clip_meshes.size(), 2u);
  EXPECT_EQ(s.meshes.at(s.volumes[0].clip_meshes[0].mesh).name, "ball");
  EXPECT_FALSE(s.volumes[0].clip_meshes[0].keep_inside);
  EXPECT_EQ(s.meshes.at(s.volumes[0].clip_meshes[1].mesh).name, "brick");
  EXPECT_TRUE(s.volumes[0].clip_meshes[1].keep_inside);
  ASSERT_EQ(s.volumes[1].clip_meshes.size(), 1u) << "several volumes share one clip mesh";
  EXPECT_EQ(s.volumes[1].clip_meshes[0].mesh, s.volumes[0].clip_meshes[0].mesh);
  EXPECT_TRUE(s.volumes[1].clip_meshes[0].keep_inside);
}

// A unit cube as an ASCII PLY file whose faces all wind inward.
std::string inward_cube_ply() {
  std::string s =
      "ply\nformat ascii 1.0\nelement vertex 8\nproperty float x\nproperty float y\n"
      "property float z\nelement face 12\nproperty list uchar int vertex_indices\nend_header\n";
  for (int i = 0; i < 8; ++i) s += fmt::format("{} {} {}\n", i & 1, (i >> 1) & 1, (i >> 2) & 1);
  const int faces[12][3] = {{0, 2, 3}, {0, 3, 1}, {4, 5, 7}, {4, 7, 6}, {0, 1, 5}, {0, 5, 4},
                            {2, 6, 7}, {2, 7, 3}, {0, 4, 6}, {0, 6, 2}, {1, 3, 7}, {1, 7, 5}};
  for (const auto& f : faces) s += fmt::format("3 {} {} {}\n", f[0], f[2], f[1]);
  return s;
}

TEST(ClipScene, AnInwardMeshIsTurnedOutward) {
  test::TempDir dir;
  dir.write("inward.ply", inward_cube_ply());
  const std::string cube =
      R"(, {"name": "cube", "type": "mesh", "source": {"file": "inward.ply"}})";
  const Scene plain = parse(scene("", "", cube), {}, dir.path());
  ASSERT_EQ(plain.meshes.back().name, "cube");
  EXPECT_NEAR(check_closed(*plain.meshes.back().mesh).signed_volume, -1.0, 1e-9);
  const Scene clipped =
      parse(scene(R"([{"mesh": "cube", "keep": "inside"}])", "", cube), {}, dir.path());
  EXPECT_NEAR(check_closed(*clipped.meshes.back().mesh).signed_volume, 1.0, 1e-9);
}

TEST(ClipScene, AnEmptyListOrAnOverrideRemovesTheClip) {
  EXPECT_TRUE(parse(scene("[]")).volumes[0].clip_meshes.empty());
  const std::string cut = scene(R"([{"mesh": "ball", "keep": "outside"}])");
  EXPECT_TRUE(parse(cut, {"objects.ct.clip=[]"}).volumes[0].clip_meshes.empty());
  EXPECT_TRUE(parse(cut, {"objects.ct.clip.0.keep=inside"}).volumes[0].clip_meshes[0].keep_inside);
}

TEST(ClipScene, EachFaultIsOneLineWithItsPath) {
  std::string e = parse_error(scene(R"([{"mesh": "bal", "keep": "outside"}])"));
  EXPECT_CONTAINS(e, "scene.json: objects[0].clip[0].mesh: no object named 'bal'");
  EXPECT_CONTAINS(e, "did you mean 'ball'");

  e = parse_error(scene("", R"([{"mesh": "ball", "keep": "outside"}, {"mesh": "axial",
                                 "keep": "inside"}])"));
  EXPECT_CONTAINS(e, "objects[1].clip[1].mesh: 'axial' is a plane; clip geometry is a closed mesh");

  e = parse_error(scene(R"([{"mesh": "pet", "keep": "inside"}])"));
  EXPECT_CONTAINS(e, "objects[0].clip[0].mesh: 'pet' is a volume");

  e = parse_error(scene(R"([{"mesh": "sheet", "keep": "inside"}])"));
  EXPECT_CONTAINS(e, "objects[0].clip[0].mesh: mesh 'sheet' is not closed: 4 open edges");

  e = parse_error(scene(R"([{"mesh": "ball", "keep": "in"}])"));
  EXPECT_CONTAINS(e, "objects[0].clip[0].keep:");
  EXPECT_CONTAINS(e, "inside");

  e = parse_error(scene(R"([{"mesh": "ball"}])"));
  EXPECT_CONTAINS(e, "objects[0].clip[0]: missing required key 'keep'");

  e = parse_error(scene(R"([{"mesh": "ball", "keep": "inside", "invert": true}])"));
  EXPECT_CONTAINS(e, "objects[0].clip[0].invert: unknown key");

  e = parse_error(scene(R"({"mesh": "ball", "keep": "inside"})"));
  EXPECT_CONTAINS(e, "objects[0].clip: expected an array");

  e = parse_error(scene(R"([{"mesh": "ball", "keep": "inside"}, {"mesh": "ball",
                            "keep": "outside"}])"));
  EXPECT_CONTAINS(e, "objects[0].clip[1].mesh: 'ball' is already clip[0] of volume 'ct'");
}

}  // namespace
}  // namespace imx
