// Tests for the volumes' "clip" lists (SPEC §7 clip geometry): names resolved to closed meshes,
// inward meshes turned outward, one error line with its JSON path per fault.
#include <filesystem>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "intermix/scene.hpp"
#include "io/mesh/mesh_topology.hpp"
#include "scene_fixture.hpp"
#include "temp_dir.hpp"

namespace imx {
namespace {

using test::error_of;
using test::parse;
using test::parse_error;

// Volumes "ct" and "pet" (clip lists given), meshes "ball" and "brick", an open "sheet", a
// plane "axial", and `more` objects.
std::string scene(const std::string& ct_clip, const std::string& pet_clip = "",
                  const std::string& more = "") {
  auto clip = [](const std::string& list) { return list.empty() ? "" : R"("clip": )" + list; };
  return test::with_objects(test::shapes_objects("ct", "pet", clip(ct_clip), clip(pet_clip)) +
                            more);
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

TEST(ClipScene, AnInwardMeshIsTurnedOutward) {
  test::TempDir dir;
  dir.write("inward.ply", test::cube_ply(/*inward=*/true));
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
