#include <gtest/gtest.h>

#include "intermix/io.hpp"
#include "intermix/scene.hpp"
#include "scene_fixture.hpp"

namespace imx {
namespace {

using test::error_of;
using test::parse;
using test::parse_error;

const std::string kTwoHeads = R"({"objects": [
  {"name": "ct", "type": "volume", "source": {"phantom": "ct-head", "size": 16},
   "transfer_function": {"points": [[-1000, 0, 0, 0, 0], [300, 1, 0.9, 0.8, 0.2]]},
   "shading": {"ambient": 0.2, "diffuse": 0.7, "specular": 0.3, "shininess": 32}},
  {"name": "copy", "type": "volume", "source": {"phantom": "ct-head", "size": 16},
   "transform": {"rotate_deg": [0, 0, 90]}, "style": "mip",
   "transfer_function": {"points": [[0, 1, 1, 1, 1]]}},
  {"name": "other", "type": "volume", "source": {"phantom": "ct-head", "size": 12},
   "style": "xray", "transfer_function": {"points": [[0, 1, 1, 1, 1]]}},
  {"name": "axial", "type": "plane", "volume": "ct", "normal": [0, 0, 1], "window": [40, 400]}
]})";

TEST(PhantomScene, PhantomsLoadOncePerSourceAndShowThroughPlanes) {
  Scene s = parse(kTwoHeads);
  ASSERT_EQ(s.volumes.size(), 3u);
  EXPECT_EQ(s.volumes[0].data.get(), s.volumes[1].data.get());
  EXPECT_NE(s.volumes[0].data.get(), s.volumes[2].data.get());
  const glm::ivec3 dims = s.volumes[0].data->dims;
  EXPECT_EQ(std::max({dims.x, dims.y, dims.z}), 16);
  EXPECT_TRUE(s.volumes[0].shading.enabled);
  EXPECT_EQ(s.volumes[1].style, VolumeStyle::mip);
  EXPECT_EQ(s.volumes[2].style, VolumeStyle::xray);
  // The rotated copy: its index x axis now points along world +y.
  glm::dvec3 x_axis(s.volumes[1].index_to_world[0]);
  glm::dvec3 original(s.volumes[0].index_to_world[0]);
  EXPECT_NEAR(x_axis.y, original.x, 1e-9);
  EXPECT_NEAR(x_axis.x, -original.y, 1e-9);
  ASSERT_EQ(s.planes.size(), 1u);
  EXPECT_EQ(s.planes[0].volume, 0);
  EXPECT_GT(s.planes[0].size.x, 0.0);
  ASSERT_EQ(s.order.size(), 4u);
  EXPECT_EQ(s.order[3].kind, ObjectKind::plane);
}

TEST(PhantomScene, DefaultSizeAndOverrides) {
  const std::string one = R"({"objects": [{"name": "s", "type": "volume",
    "source": {"phantom": "sphere"}, "transfer_function": {"points": [[0, 1, 1, 1, 1]]}}]})";
  Scene s = parse(one, {"objects.s.source.size=20"});
  EXPECT_EQ(
      std::max({s.volumes[0].data->dims.x, s.volumes[0].data->dims.y, s.volumes[0].data->dims.z}),
      20);
}

TEST(PhantomScene, UnknownPhantomSuggestsAName) {
  std::string msg = error_of([&] { parse(kTwoHeads, {"objects.ct.source.phantom=ct-haed"}); });
  EXPECT_CONTAINS(msg,
                  "scene.json: objects[0].source.phantom: \"ct-haed\" is not a built-in "
                  "phantom (did you mean 'ct-head'?)");
  msg = error_of([&] { parse(kTwoHeads, {"objects.ct.source.size=4"}); });
  EXPECT_CONTAINS(msg, "objects[0].source.size: 4 is not in [8, 1024]");
}

}  // namespace
}  // namespace imx
