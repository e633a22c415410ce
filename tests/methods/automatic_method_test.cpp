// `auto` picks by the scene's content: the rules of automatic_method.hpp, through resolve_method
// as render() and the CLI call it.
#include <gtest/gtest.h>

#include <string>

#include "intermix/render.hpp"
#include "intermix/scene.hpp"

namespace imx {
namespace {

// A scene of the given objects (JSON array elements), small phantoms and primitives.
ResolvedMethod auto_for(const std::string& objects) {
  const std::string text = R"({"image": {"width": 8, "height": 8}, "objects": [)" + objects + "]}";
  return resolve_method(parse_scene(text, ".", "auto test"), "auto");
}

const std::string kVolume =
    R"({"name": "v", "type": "volume", "source": {"phantom": "sphere", "size": 8}})";
const std::string kVolume2 =
    R"({"name": "w", "type": "volume", "source": {"phantom": "sphere", "size": 8}})";
const std::string kMesh =
    R"({"name": "m", "type": "mesh", "source": {"primitive": "sphere", "radius": 2}})";
const std::string kPlane = R"({"name": "p", "type": "plane", "center": [0, 0, 0],
    "normal": [0, 0, 1], "size": [4, 4]})";

TEST(AutomaticMethod, PicksByContent) {
  EXPECT_EQ(auto_for(kVolume).name, "mdvr");
  EXPECT_EQ(auto_for(kVolume + "," + kVolume2).name, "zslab-hybrid");
  EXPECT_EQ(auto_for(kVolume + "," + kMesh).name, "zslab-hybrid");
  EXPECT_EQ(auto_for(kVolume + "," + kPlane).name, "peel");
  EXPECT_EQ(auto_for(kMesh + "," + kPlane).name, "dfb-sfm");
  EXPECT_EQ(auto_for(kVolume + "," + kVolume2).reason, "several volumes");
  // A method the scene names is kept.
  EXPECT_EQ(resolve_method(parse_scene(R"({"image": {"width": 8, "height": 8}, "objects": [)" +
                                           kVolume + R"(], "render": {"method": "peel"}})",
                                       ".", "named"),
                           "")
                .name,
            "peel");
}

}  // namespace
}  // namespace imx
