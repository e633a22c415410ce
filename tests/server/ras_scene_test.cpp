// A scene file in RAS ("space": "RAS") in the viewer: the page sends LPS (the scene as parsed),
// and the session writes each edit back in the document's RAS, so that the camera, a clip plane
// and a plane's centre land where the page put them, and stay there over later edits.
#include <filesystem>
#include <fstream>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "server/viewer_state.hpp"
#include "temp_dir.hpp"

namespace imx::server {
namespace {

using Json = nlohmann::json;

TEST(RasScene, EditsLandWhereThePageSentThem) {
  test::TempDir dir;
  const Json scene = {
      {"space", "RAS"},
      {"camera", {{"eye", {10, 400, 20}}, {"target", {10, 0, 20}}, {"up", {0, 0, 1}}}},
      {"image", {{"width", 16}, {"height", 16}}},
      {"objects",
       {{{"name", "head"},
         {"type", "volume"},
         {"source", {{"phantom", "ct-head"}, {"size", 16}}},
         {"transfer_function", {{"preset", "ct-bone"}}}},
        {{"name", "axial"},
         {"type", "plane"},
         {"volume", "head"},
         {"center", {0, 0, 0}},
         {"normal", {0, 0, 1}}}}}};
  const std::filesystem::path file = dir.path() / "ras.json";
  std::ofstream(file) << scene.dump();
  ViewerState state = load_viewer_state(file);
  // Parsed into LPS: the RAS eye (10, 400, 20) is LPS (-10, -400, 20).
  EXPECT_EQ(state.scene().camera.eye, glm::dvec3(-10, -400, 20));

  apply_edit(state, Json{{"type", "camera"},
                         {"eye", {-10, -300, 20}},
                         {"target", {-10, 0, 20}},
                         {"up", {0, 0, 1}}});
  EXPECT_EQ(state.scene().camera.eye, glm::dvec3(-10, -300, 20));
  EXPECT_EQ(state.document.json()["camera"]["eye"], Json({10.0, 300.0, 20.0}));  // RAS in the file
  // A move composes in LPS too: from where the session is, 100 mm closer.
  apply_edit(state,
             Json{{"type", "camera"},
                  {"from", {{"eye", {-10, -300, 20}}, {"target", {-10, 0, 20}}, {"up", {0, 0, 1}}}},
                  {"eye", {-10, -200, 20}},
                  {"target", {-10, 0, 20}},
                  {"up", {0, 0, 1}}});
  EXPECT_NEAR(state.scene().camera.eye.y, -200.0, 1e-9);
  EXPECT_NEAR(state.scene().camera.eye.x, -10.0, 1e-9);

  apply_edit(state, Json{{"type", "edit"},
                         {"object", "head"},
                         {"clip_planes", {{{"point", {5, 6, 7}}, {"normal", {1, 0, 0}}}}}});
  ASSERT_EQ(state.scene().volumes[0].clip_planes.size(), 1u);
  EXPECT_EQ(state.scene().volumes[0].clip_planes[0].point, glm::dvec3(5, 6, 7));
  EXPECT_EQ(state.scene().volumes[0].clip_planes[0].normal, glm::dvec3(1, 0, 0));

  apply_edit(state, Json{{"type", "edit"}, {"object", "axial"}, {"center", {3, -4, 5}}});
  EXPECT_EQ(state.scene().planes[0].center, glm::dvec3(3, -4, 5));
  // An unrelated edit keeps all of them where they are.
  apply_edit(state, Json{{"type", "edit"}, {"object", "head"}, {"opacity", 0.5}});
  EXPECT_EQ(state.scene().volumes[0].clip_planes[0].point, glm::dvec3(5, 6, 7));
  EXPECT_EQ(state.scene().planes[0].center, glm::dvec3(3, -4, 5));
  EXPECT_NEAR(state.scene().camera.eye.y, -200.0, 1e-9);
}

}  // namespace
}  // namespace imx::server
