#include "scene/overrides.hpp"

#include <gtest/gtest.h>

#include "expect_error.hpp"

namespace imx::scene_json {
namespace {

using nlohmann::json;
using test::error_of;

json sample() {
  return json::parse(R"({
    "image": {"width": 512},
    "objects": [
      {"name": "ct", "type": "volume"},
      {"name": "implant", "type": "mesh", "material": {"opacity": 1}}
    ]
  })");
}

TEST(Overrides, SetsNumbersByDottedPath) {
  json j = sample();
  apply_override(j, "image.width=256", "s.json");
  EXPECT_EQ(j["image"]["width"], 256);
}

TEST(Overrides, IndexesArraysByNumberBracketOrName) {
  json j = sample();
  apply_override(j, "objects.1.material.opacity=0.3", "s.json");
  EXPECT_DOUBLE_EQ(j["objects"][1]["material"]["opacity"].get<double>(), 0.3);
  apply_override(j, "objects[1].material.opacity=0.4", "s.json");
  EXPECT_DOUBLE_EQ(j["objects"][1]["material"]["opacity"].get<double>(), 0.4);
  apply_override(j, "objects.implant.material.opacity=0.5", "s.json");
  EXPECT_DOUBLE_EQ(j["objects"][1]["material"]["opacity"].get<double>(), 0.5);
  apply_override(j, "objects[implant].material.color=[1,0,0]", "s.json");
  EXPECT_EQ(j["objects"][1]["material"]["color"], json::parse("[1,0,0]"));
}

TEST(Overrides, CreatesMissingObjects) {
  json j = sample();
  apply_override(j, "render.spp=4", "s.json");
  EXPECT_EQ(j["render"]["spp"], 4);
  apply_override(j, "objects.ct.transform.translate=[1, 2, 3]", "s.json");
  EXPECT_EQ(j["objects"][0]["transform"]["translate"], json::parse("[1,2,3]"));
}

TEST(Overrides, NonJsonValuesAreStrings) {
  json j = sample();
  apply_override(j, "render.method=zslab-hybrid", "s.json");
  EXPECT_EQ(j["render"]["method"], "zslab-hybrid");
  apply_override(j, "render.method=\"peel\"", "s.json");
  EXPECT_EQ(j["render"]["method"], "peel");
  apply_override(j, "camera.fov_deg=1e999", "s.json");  // overflows JSON numbers: a string
  EXPECT_TRUE(j["camera"]["fov_deg"].is_string());
  apply_override(j, "render.interpolation=", "s.json");
  EXPECT_EQ(j["render"]["interpolation"], "");
}

TEST(Overrides, ReachIntoCsgExpressions) {
  json j = json::parse(R"({"csg": {"op": "union", "a": {"op": "difference", "a": "x", "b": "y"},
                                    "of": ["p", "q", "r"]}})");
  apply_override(j, "csg.a.b=ball", "s.json");
  EXPECT_EQ(j["csg"]["a"]["b"], "ball");  // a bare word: a string
  apply_override(j, "csg.of.2=ball", "s.json");
  EXPECT_EQ(j["csg"]["of"][2], "ball");
  apply_override(j, R"(csg.of[0]={"object": "ct", "presence": "region"})", "s.json");
  EXPECT_EQ(j["csg"]["of"][0]["presence"], "region");
  EXPECT_CONTAINS(error_of([&] { apply_override(j, "csg.of.3=ball", "s.json"); }),
                  "csg.of has 3 elements, there is no element 3");
  apply_override(j, "csg=null", "s.json");
  EXPECT_TRUE(j["csg"].is_null());
  // From null, a path builds the operator up again.
  apply_override(j, "csg.op=intersection", "s.json");
  apply_override(j, "csg.a=ball", "s.json");
  EXPECT_EQ(j["csg"], json::parse(R"({"op": "intersection", "a": "ball"})"));
}

TEST(Overrides, BadPathsNameTheOverride) {
  json j = sample();
  std::string msg = error_of([&] { apply_override(j, "image.width.x=3", "s.json"); });
  EXPECT_CONTAINS(msg, "s.json: --set image.width.x=3:");
  EXPECT_CONTAINS(msg, "image.width is a number");
  msg = error_of([&] { apply_override(j, "objects.7.name=x", "s.json"); });
  EXPECT_CONTAINS(msg, "objects has 2 elements");
  msg = error_of([&] { apply_override(j, "objects.implnt.name=x", "s.json"); });
  EXPECT_CONTAINS(msg, "no element named 'implnt' (did you mean 'implant'?)");
  msg = error_of([&] { apply_override(j, "image.width", "s.json"); });
  EXPECT_CONTAINS(msg, "expected key=value");
  for (const char* bad : {"=3", "a..b=1", "a.=1", "a[=1", "a[]=1", "a]=1", ".a=1"})
    EXPECT_CONTAINS(error_of([&] { apply_override(j, bad, "s.json"); }), "is not a key path");
}

}  // namespace
}  // namespace imx::scene_json
