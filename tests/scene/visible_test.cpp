// The objects' "visible" key: a hidden object keeps its data and its place but shows nothing
// (a mesh's and its interior's opacity, a plane's opacity, a volume's alphas become 0).
#include <gtest/gtest.h>

#include "core/colour.hpp"
#include "intermix/scene.hpp"
#include "scene_fixture.hpp"

namespace imx {
namespace {

using test::parse;
using test::parse_error;

std::string scene(const std::string& visible) {
  return R"({"objects": [
    {"name": "ct", "type": "volume", "source": {"phantom": "ct-head", "size": 16},
     "transfer_function": {"points": [[0, 1, 0.5, 0, 0.25], [100, 1, 1, 1, 0.75]]})" +
         visible + R"(},
    {"name": "ball", "type": "mesh", "source": {"primitive": "sphere", "radius": 10},
     "material": {"opacity": 0.5}, "interior": {"opacity": 0.3})" +
         visible + R"(},
    {"name": "cube", "type": "mesh", "source": {"primitive": "box", "size": 8})" +
         visible + R"(},
    {"name": "cut", "type": "plane", "volume": "ct", "normal": [0, 0, 1], "opacity": 0.8)" +
         visible + R"(}],
    "csg": {"op": "difference", "a": "ball", "b": "cube"}})";
}

TEST(Visible, DefaultsToShown) {
  const Scene shown = parse(scene(""));
  const Scene also = parse(scene(R"(, "visible": true)"));
  EXPECT_EQ(shown.meshes[0].material.opacity, 0.5f);
  EXPECT_EQ(shown.meshes[0].interior->opacity, 0.3f);
  EXPECT_EQ(also.meshes[0].material.opacity, 0.5f);
  EXPECT_EQ(also.planes[0].opacity, 0.8f);
  EXPECT_EQ(also.volumes[0].transfer_function.points[1].rgba.a, 0.75f);
}

TEST(Visible, HiddenObjectsShowNothingButKeepTheirData) {
  const Scene s = parse(scene(R"(, "visible": false)"));
  const TransferFunction& tf = s.volumes[0].transfer_function;
  ASSERT_EQ(tf.points.size(), 2u);
  for (const TfPoint& p : tf.points) EXPECT_EQ(p.rgba.a, 0.0f);
  EXPECT_EQ(tf.points[0].rgba.g, srgb_decode(0.5f));  // colours stay (decoded, docs/colour.md)
  ASSERT_NE(s.volumes[0].data, nullptr);
  EXPECT_EQ(s.meshes[0].material.opacity, 0.0f);
  EXPECT_EQ(s.meshes[0].interior->opacity, 0.0f);
  EXPECT_EQ(s.meshes[1].material.opacity, 0.0f);
  EXPECT_FALSE(s.meshes[1].mesh->triangles.empty());
  EXPECT_EQ(s.planes[0].opacity, 0.0f);
  EXPECT_EQ(s.planes[0].volume, 0);  // a hidden volume still feeds its planes
  ASSERT_TRUE(s.csg.has_value());    // and hidden meshes are still CSG primitives
}

TEST(Visible, MustBeABoolean) {
  EXPECT_CONTAINS(parse_error(scene(R"(, "visible": 0)")),
                  "scene.json: objects[0].visible: expected true or false, got number 0");
  EXPECT_CONTAINS(parse_error(R"({"objects": [{"name": "b", "type": "mesh", "visble": false,
                  "source": {"primitive": "sphere", "radius": 1}}]})"),
                  "did you mean 'visible'");
}

}  // namespace
}  // namespace imx
